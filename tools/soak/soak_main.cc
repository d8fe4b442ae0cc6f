/// viscera-soak: runs a viscerad for a while under every fault a training centre's network can
/// produce (docs/reliability.md), and checks that it holds: memory and threads flat, a witness
/// session at its rate, every record complete and replaying bit for bit, a clean exit.
/// Loopback only: run it inside tests/e2e/in_netns.sh (CI does; ctest soak.short).
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <viscera_proto/session_status_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/wire_counts.h"
#include "client/keep_alive.h"
#include "client/session_client.h"
#include "session/replay.h"
#include "tools/soak/memory_growth.h"
#include "tools/soak/soak_cadence.h"
#include "tools/soak/soak_faults.h"
#include "tools/soak/soak_records.h"

extern char** environ;

namespace {

using viscera::soak::Created;
using viscera_proto::session_request_t;
using viscera_proto::session_status_t;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string viscerad, viscera, scene_dir, work;
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  double seconds = 20.0;
  double max_seconds = 0.0;  // 0: three times `seconds`
  double rss_bound_mb = 16.0;
  int warm_periods = 8;
  int judged_periods = 2;
  double min_rate_fraction = 0.9;
};

// A tube with one grasper: inline, so every cycle also exercises the inline scene path.
constexpr char kToolScene[] =
    "[simulation]\nrate_hz = 100\nintegrator = \"implicit\"\n"
    "[intestine]\nlength = 0.4\nradius = 0.0125\nmass = 0.1\ncontrol_points = "
    "21\nstretch_stiffness = 100.0\n"
    "bend_stiffness = 1.0e-4\ndamping = 2.0\nspring_damping = 2.0\npinned = [\"start\", \"end\"]\n"
    "[intestine.shape]\nkind = \"straight\"\nstart = [-0.2, 0.0, 0.0125]\ndirection = [1.0, 0.0, "
    "0.0]\n"
    "[[obstacle]]\nkind = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
    "[[tool]]\nname = \"grasper\"\nport = [0.0, 0.0, 0.3]\n";

void Sleep(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

pid_t StartServer(const Options& o, const std::string& records) {
  std::vector<std::string> args = {
      o.viscerad, "--server-id",     "soak",      "--lcm-url",
      o.url,      "--scene-dir",     o.scene_dir, "--log-dir",
      records,    "--max-sessions",  "8",         "--max-creates-per-minute",
      "100000",   "--session-lease", "30",        "--max-message-size",
      "65536"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string err = o.work + "/viscerad.err";
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

std::optional<session_status_t> StatusOf(viscera::client::SessionClient& client, int64_t id) {
  const auto replies =
      client.Request(viscera::client::MakeRequest(session_request_t::kStatus, id), 2.0);
  if (replies.empty() || replies.front().num_sessions < 1) return std::nullopt;
  return replies.front().sessions[0];
}

// The last status a record holds (its final one, kStopped, when the session was destroyed).
int8_t LastRecordedState(const std::string& path) {
  lcm::LogFile log(path, "r");
  int8_t state = 0;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (std::string(e->channel).rfind(viscera::bus::kStatusPrefix, 0) != 0) continue;
    session_status_t s;
    if (viscera::bus::ArrayCountsFit<session_status_t>(static_cast<const uint8_t*>(e->data),
                                                       e->datalen) &&
        s.decode(e->data, 0, e->datalen) == e->datalen) {
      state = s.state;
    }
  }
  return state;
}

int Run(const Options& o) {
  namespace fs = std::filesystem;
  const std::string records = o.work + "/records";
  fs::remove_all(records);  // a previous run's records are not this run's
  fs::create_directories(records);
  const std::string script = o.work + "/push.csv";
  std::ofstream(script) << "t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,grasper,0,0,0.1,1,0,0,0,1\n"
                           "2,grasper,0,0,0.005,1,0,0,0,1\n4,grasper,0,0,0.1,1,0,0,0,1\n";
  nlohmann::ordered_json report;
  const pid_t server = StartServer(o, records);
  if (server < 0) {
    std::fprintf(stderr, "viscera-soak: cannot start %s\n", o.viscerad.c_str());
    return 1;
  }
  viscera::client::SessionClient client(o.url, nullptr);
  if (!client.FindServer("soak", 10.0)) {
    std::fprintf(stderr, "viscera-soak: no heartbeat from viscerad within 10 s\n");
    kill(server, SIGKILL);
    return 1;
  }
  const auto idle = viscera::soak::Figures(server);
  const Created witness = viscera::soak::CreateSession(client, "soak", "", kToolScene, -1.0);
  if (witness.id == 0) {
    std::fprintf(stderr, "viscera-soak: witness session refused: %s\n", witness.refusal.c_str());
    kill(server, SIGKILL);
    return 1;
  }
  viscera::client::KeepAlive keep_witness(&client, witness.id, witness.token, 1.0);

  int64_t cycles = 0, created = 0, destroyed = 0, drivers_killed = 0, poses_flooded = 0,
          malformed = 0, oversize_answered = 0, scenes_refused = 0, blowups = 0,
          blowups_recovered = 0, rate_samples = 0, creates_unanswered = 0, rate_ok = 0;
  double min_rate = 1e9;
  viscera::soak::ProcessFigures peak{0, 0};
  std::vector<Created> live;
  std::vector<int64_t> rss_series;  // every 10th cycle (kB)
  // Warm counts in cycles, not seconds: the server grows to its working size by the faults it has
  // run (measured: in steps at its blow-up cycles, larger and later under load), and a loaded
  // machine fits fewer cycles into a quarter of the time. The run goes on past `seconds`, up to
  // `max_seconds`, until enough cycles after the baseline can be judged (docs/reliability.md).
  const viscera::soak::GrowthPolicy memory_policy{
      .warm_cycles = o.warm_periods * viscera::soak::kCadencePeriod,
      .warm_seconds = o.seconds / 4,
      .judged_cycles = o.judged_periods * viscera::soak::kCadencePeriod,
      .bound_mb = o.rss_bound_mb};
  std::vector<viscera::soak::RssSample> rss_samples;
  std::ofstream rss_csv(o.work + "/rss.csv");
  rss_csv << "cycle,seconds,rss_kb\n";
  const auto start = Clock::now();
  const auto end = start + std::chrono::duration<double>(o.seconds);
  const auto cap =
      start + std::chrono::duration<double>(o.max_seconds > 0 ? o.max_seconds : 3 * o.seconds);
  const auto can_judge = [&] {
    return viscera::soak::JudgeGrowth(rss_samples, memory_policy).outcome !=
           viscera::soak::GrowthVerdict::Outcome::kTooShort;
  };
  while (Clock::now() < end || (Clock::now() < cap && !can_judge())) {
    ++cycles;
    // a session per cycle (frames every other one), flooded, driven by a client that is killed
    const Created s = viscera::soak::CreateSession(client, "soak", "", kToolScene,
                                                   viscera::soak::FramesOn(cycles) ? 10.0 : -1.0);
    if (s.id != 0) {
      ++created;
      live.push_back(s);
      viscera::soak::FloodPoses(client.bus(), s, 2000);
      poses_flooded += 2000;
      const pid_t driver = viscera::soak::StartDriver(o.viscera, o.url, s.id, s.token, script);
      Sleep(0.3);
      if (driver > 0 && kill(driver, SIGKILL) == 0) ++drivers_killed;
      if (driver > 0) waitpid(driver, nullptr, 0);
    } else {
      ++creates_unanswered;
    }
    malformed += viscera::soak::SendMalformed(client.bus(), s.id != 0 ? s.id : witness.id,
                                              static_cast<uint32_t>(cycles));
    if (!viscera::soak::SendOversize(client, "soak", 65536).empty()) ++oversize_answered;
    if (viscera::soak::HostileScenes(cycles))
      scenes_refused += viscera::soak::SendMalformedScenes(client, "soak");
    if (viscera::soak::BlowUp(cycles)) {
      const Created bad =
          viscera::soak::CreateSession(client, "soak", "", viscera::soak::UnstableScene(), -1.0);
      if (bad.id != 0) {
        ++blowups;
        // it blows up within its first steps; a busy machine may take a while to run them
        for (const auto give_up = Clock::now() + std::chrono::seconds(5); Clock::now() < give_up;
             Sleep(0.1)) {
          const auto st = StatusOf(client, bad.id);
          if (st && st->recoveries > 0 && st->state == session_status_t::kRunning) {
            ++blowups_recovered;
            break;
          }
        }
        if (viscera::soak::DestroySession(client, bad)) ++destroyed;
      } else {
        ++creates_unanswered;
      }
    }
    // sessions live about two cycles
    while (live.size() > 2) {
      if (viscera::soak::DestroySession(client, live.front())) ++destroyed;
      live.erase(live.begin());
    }
    if (const auto w = StatusOf(client, witness.id)) {
      ++rate_samples;
      min_rate = std::min(min_rate, w->achieved_rate_hz);
      if (w->achieved_rate_hz >= o.min_rate_fraction * w->rate_hz) ++rate_ok;
    }
    const auto f = viscera::soak::Figures(server);
    const double t = std::chrono::duration<double>(Clock::now() - start).count();
    rss_samples.push_back({cycles, t, f.rss_kb});
    rss_csv << cycles << ',' << t << ',' << f.rss_kb << '\n';
    if (cycles % 10 == 0) rss_series.push_back(f.rss_kb);
    peak.rss_kb = std::max(peak.rss_kb, f.rss_kb);
    peak.threads = std::max(peak.threads, f.threads);
  }
  const double soaked_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const auto loaded = viscera::soak::Figures(server);
  for (const Created& s : live) destroyed += viscera::soak::DestroySession(client, s) ? 1 : 0;
  destroyed += viscera::soak::DestroySession(client, witness) ? 1 : 0;
  // render threads end after their frame: poll until the threads are back to idle
  auto after = viscera::soak::Figures(server);
  for (const auto give_up = Clock::now() + std::chrono::seconds(10);
       after.threads > idle.threads && Clock::now() < give_up;
       after = viscera::soak::Figures(server)) {
    Sleep(0.1);
  }
  const auto left =
      client.Request(viscera::client::MakeRequest(session_request_t::kList, 0), 2.0, true);
  const int sessions_left = left.empty() ? -1 : left.front().num_sessions;
  std::string thread_names;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(server) + "/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    std::getline(comm, name);
    thread_names += (thread_names.empty() ? "" : ",") + name;
  }
  kill(server, SIGTERM);
  int status = 0;
  waitpid(server, &status, 0);
  const bool clean_exit = WIFEXITED(status) && WEXITSTATUS(status) == 0;

  int64_t records_total = 0, records_exact = 0, records_stopped = 0;
  std::string record_error;
  for (const auto& entry : fs::directory_iterator(records)) {
    if (entry.path().extension() != ".lcmlog") continue;  // the assessments written beside them
    ++records_total;
    try {
      const auto r = viscera::session::ReplayRecord(entry.path().string());
      if (r.max_deviation == 0.0) ++records_exact;  // 0 steps too: destroyed before its first
    } catch (const std::exception& e) {
      record_error = entry.path().filename().string() + ": " + e.what();
    }
    if (LastRecordedState(entry.path().string()) == session_status_t::kStopped) ++records_stopped;
  }

  const auto memory = viscera::soak::JudgeGrowth(rss_samples, memory_policy);
  const bool memory_ok = memory.outcome == viscera::soak::GrowthVerdict::Outcome::kFlat;
  // Mesa starts one shader-cache thread ("disk$0") with the first frame and keeps it
  const bool threads_ok = after.threads >= 0 && after.threads <= idle.threads + 1;
  const bool rate_kept = rate_samples > 0 && rate_ok >= (rate_samples * 95 + 99) / 100;
  const bool records_ok = viscera::soak::RecordsAccountedFor(records_total, created + blowups + 1,
                                                             creates_unanswered) &&
                          records_exact == records_total && records_stopped == records_total;
  // a reply may be lost on a loaded machine (UDP): most oversize creates must be answered
  const bool faults_ok =
      drivers_killed > 0 && oversize_answered * 10 >= cycles * 9 && blowups_recovered == blowups;
  report["seconds"] = o.seconds;
  report["seconds_soaked"] = soaked_seconds;
  report["cycles"] = cycles;
  report["sessions_created"] = created + blowups + 1;
  report["creates_unanswered"] = creates_unanswered;
  report["sessions_destroyed"] = destroyed;
  report["faults"] = {
      {"clients_killed", drivers_killed},         {"poses_flooded", poses_flooded},
      {"malformed_datagrams", malformed},         {"oversize_answered", oversize_answered},
      {"hostile_scenes_refused", scenes_refused}, {"blowups", blowups},
      {"blowups_recovered", blowups_recovered}};
  report["rss_kb"] = {{"idle", idle.rss_kb},
                      {"baseline", memory.baseline.rss_kb},
                      {"last_cycle", memory.last.rss_kb},
                      {"end_loaded", loaded.rss_kb},
                      {"peak", peak.rss_kb},
                      {"after", after.rss_kb},
                      {"every_10_cycles", rss_series}};
  report["memory"] = {{"verdict", memory.message},
                      {"warm_cycles", memory_policy.warm_cycles},
                      {"warm_seconds", memory_policy.warm_seconds},
                      {"baseline_cycle", memory.baseline.cycle},
                      {"baseline_seconds", memory.baseline.seconds},
                      {"last_cycle", memory.last.cycle},
                      {"judged_cycles", memory.judged_cycles},
                      {"judged_cycles_needed", memory_policy.judged_cycles},
                      {"growth_mb", memory.growth_mb},
                      {"bound_mb", o.rss_bound_mb}};
  report["threads"] = {{"idle", idle.threads},
                       {"peak", peak.threads},
                       {"after", after.threads},
                       {"after_names", thread_names},
                       {"sessions_left", sessions_left}};
  report["witness"] = {{"samples", rate_samples},
                       {"at_rate", rate_ok},
                       {"min_rate_hz", min_rate},
                       {"min_fraction", o.min_rate_fraction}};
  report["records"] = {{"total", records_total},
                       {"replay_exact", records_exact},
                       {"final_status_stopped", records_stopped},
                       {"error", record_error}};
  report["clean_exit"] = clean_exit;
  const bool ok = memory_ok && threads_ok && rate_kept && records_ok && faults_ok && clean_exit;
  report["ok"] = ok;
  report["failed"] = nlohmann::ordered_json::array();
  for (const auto& [name, good] : {std::pair{"memory", memory_ok},
                                   {"threads", threads_ok},
                                   {"witness_rate", rate_kept},
                                   {"records", records_ok},
                                   {"faults", faults_ok},
                                   {"clean_exit", clean_exit}}) {
    if (!good) report["failed"].push_back(name);
  }
  std::printf("%s\n", report.dump(2).c_str());
  return ok ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "viscera-soak: a viscerad under faults for a while; memory, threads, rates and records "
      "checked"};
  Options o;
  app.add_option("--viscerad", o.viscerad, "viscerad binary")->required();
  app.add_option("--viscera", o.viscera, "viscera client binary")->required();
  app.add_option("--scene-dir", o.scene_dir, "Scene directory (needs hanging.toml)")->required();
  app.add_option("--work", o.work, "Scratch directory (records, logs)")->required();
  app.add_option("--lcm-url", o.url, "LCM URL (loopback only)")->capture_default_str();
  app.add_option("--seconds", o.seconds, "How long to soak")->capture_default_str();
  app.add_option("--max-seconds", o.max_seconds,
                 "Soak on past --seconds, up to this long, until the memory check has enough "
                 "cycles (0: 3 x --seconds)")
      ->capture_default_str();
  app.add_option("--rss-bound-mb", o.rss_bound_mb, "Largest RSS growth allowed after warm-up (MB)")
      ->capture_default_str();
  app.add_option("--warm-periods", o.warm_periods,
                 "The RSS baseline waits this many cadences of 10 cycles, each with every kind of "
                 "fault (and the first "
                 "quarter)")
      ->capture_default_str();
  app.add_option("--judged-periods", o.judged_periods,
                 "Cadences of 10 cycles after the RSS baseline the memory check needs")
      ->capture_default_str();
  app.add_option("--min-rate-fraction", o.min_rate_fraction,
                 "A witness status sample is at rate when achieved >= this x configured (95 % of "
                 "samples must be)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    return Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viscera-soak: %s\n", e.what());
    return 1;
  }
}
