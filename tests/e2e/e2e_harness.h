#pragma once
// Helpers for end-to-end tests that run the real viscerad and viscera over real UDP
// multicast. The tests run inside tests/e2e/in_netns.sh (a private, loopback-only network
// namespace), so every datagram stays in it.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

extern char** environ;

namespace viscera::e2e {

inline constexpr char kUrl[] = "udpm://239.255.76.67:7667?ttl=0";

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A private scratch directory per test (records, keys, session store).
inline std::string ScratchDir() {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir =
      ::testing::TempDir() + "/viscera_e2e_" + info->name() + "_" + std::to_string(getpid());
  std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());
  return dir;
}

/// A running viscerad; SIGTERM (then waits) on Stop or destruction.
class Daemon {
 public:
  Daemon(const std::string& server_id, std::vector<std::string> extra, const std::string& dir,
         const std::string& url = kUrl)
      : stderr_path_(dir + "/viscerad-" + server_id + ".err") {
    std::vector<std::string> args = {VISCERAD, "--server-id", server_id, "--lcm-url", url};
    // the repository's scenes unless the test names its own directory
    if (std::find(extra.begin(), extra.end(), "--scene-dir") == extra.end()) {
      args.insert(args.end(), {"--scene-dir", std::string(VISCERA_SOURCE_DIR) + "/scenes"});
    }
    // A fixed session limit unless the test sets its own: the measured default (a cavity
    // session's step and frame cost against 70 % of the cores, docs/capacity.md) sits near 2
    // sessions on a 2-core machine, and a busy or slow moment made it 1 and refused a test's
    // second create ("every server is full"). The measurement has its own tests.
    if (std::find(extra.begin(), extra.end(), "--max-sessions") == extra.end()) {
      args.insert(args.end(), {"--max-sessions", "4"});
    }
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 2, stderr_path_.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    EXPECT_EQ(posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Daemon() {
    if (pid_ > 0) Stop();
  }
  /// Sends `signal` and waits. @return the exit status (128 + signal when killed).
  int Stop(int signal = SIGTERM) {
    kill(pid_, signal);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  /// Waits up to `timeout_s` for the process to exit. @return its exit status, or -1 if it runs on.
  int WaitExit(double timeout_s) {
    const auto give_up =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < give_up) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }
  pid_t pid() const { return pid_; }
  bool Alive() const {
    return pid_ > 0 && kill(pid_, 0) == 0 && waitpid(pid_, nullptr, WNOHANG) == 0;
  }
  std::string Stderr() const { return ReadFile(stderr_path_); }

 private:
  std::string stderr_path_;
  pid_t pid_ = -1;
};

struct CliResult {
  int rc = -1;
  std::string out;
  nlohmann::json json() const {
    try {
      return nlohmann::json::parse(out);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not JSON (" << e.what() << "): " << out;
      return {};
    }
  }
};

/// Runs the real `viscera` with `args` (URL and session store added), capturing stdout;
/// stderr goes to the test log.
inline CliResult Viscera(const std::string& dir, const std::string& args) {
  const std::string command = std::string(VISCERA_CLI) + " " + args + " --lcm-url '" + kUrl +
                              "' --sessions '" + dir + "/sessions.json'";
  CliResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof(buf), pipe)) > 0;) r.out.append(buf, n);
  const int status = pclose(pipe);
  r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// Creates a session with `args` and returns its create JSON (asserting success). Waits up
/// to 30 s to hear a server: a Daemon just spawned may beat for the first time seconds
/// later on a busy machine (the client stops listening once one is heard).
inline nlohmann::json Create(const std::string& dir, const std::string& args) {
  const CliResult r = Viscera(dir, "create " + args + " --timeout 30 --json");
  EXPECT_EQ(r.rc, 0) << r.out;
  return r.rc == 0 ? r.json() : nlohmann::json();
}

/// The status of session `id` as `viscera status --json` prints it (`extra`: more flags).
inline nlohmann::json Status(const std::string& dir, int64_t id, const std::string& extra = "") {
  const CliResult r = Viscera(dir, "status " + std::to_string(id) + " --json " + extra);
  EXPECT_EQ(r.rc, 0) << r.out;
  return r.rc == 0 ? r.json() : nlohmann::json();
}

/// The same, or null when no answer came (a busy machine can miss the CLI's 2 s): for polls,
/// which ask again rather than fail on one late answer.
inline nlohmann::json TryStatus(const std::string& dir, int64_t id, const std::string& extra = "") {
  const CliResult r = Viscera(dir, "status " + std::to_string(id) + " --json " + extra);
  return r.rc == 0 ? r.json() : nlohmann::json();
}

inline void Sleep(double seconds) {
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

}  // namespace viscera::e2e
