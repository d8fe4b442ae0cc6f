#pragma once
/// The commands of `viscera`, one set-up and one run function each: the set-up adds the
/// command's own options to its CLI11 subcommand (the common ones belong to `viscera`), the
/// run does the command once the command line is parsed. `url` is the resolved LCM URL.
#include <cstdint>
#include <functional>
#include <string>

#include <CLI/CLI.hpp>
#include <viscera_proto/session_request_t.hpp>

#include "client/cli/common.h"

namespace viscera::client::cli {

using SetUpFunction = void (*)(CLI::App* cmd, Common* common);
using RunFunction = int (*)(const std::string& url, const Common& common);

/// A row of the command table: what `viscera --help` lists and how to run it.
struct Command {
  const char* name;
  const char* help;      ///< one line, for `viscera --help`
  const char* examples;  ///< a few lines, for the command's --help
  SetUpFunction set_up;
  RunFunction run;
};

void SetUpServers(CLI::App* cmd, Common* common);
int RunServers(const std::string& url, const Common& common);

void SetUpCreate(CLI::App* cmd, Common* common);
int RunCreate(const std::string& url, const Common& common);

void SetUpList(CLI::App* cmd, Common* common);
int RunList(const std::string& url, const Common& common);

void SetUpStatus(CLI::App* cmd, Common* common);
int RunStatus(const std::string& url, const Common& common);

void SetUpReport(CLI::App* cmd, Common* common);
int RunReport(const std::string& url, const Common& common);

void SetUpDrive(CLI::App* cmd, Common* common);
int RunDrive(const std::string& url, const Common& common);

void SetUpHaptic(CLI::App* cmd, Common* common);
int RunHaptic(const std::string& url, const Common& common);

void SetUpCamera(CLI::App* cmd, Common* common);
int RunCamera(const std::string& url, const Common& common);

/// destroy, reset, pause, resume, camera: one request with the session's token, `fill` setting
/// what the command adds; prints the reply (or why it failed) and returns the exit code.
int RunSessionRequest(const std::string& url, const Common& c, int8_t command, int64_t id,
                      const std::function<void(viscera_proto::session_request_t*)>& fill = nullptr);

// destroy, pause, resume, reset: a session id and its token, nothing else
void SetUpSessionCommand(CLI::App* cmd, Common* common);
int RunDestroy(const std::string& url, const Common& common);
int RunPause(const std::string& url, const Common& common);
int RunResume(const std::string& url, const Common& common);
int RunReset(const std::string& url, const Common& common);

// frames, record, view: listen to one session's frame stream
void SetUpFrames(CLI::App* cmd, Common* common);
int RunFrames(const std::string& url, const Common& common);
void SetUpRecord(CLI::App* cmd, Common* common);
int RunRecord(const std::string& url, const Common& common);
void SetUpView(CLI::App* cmd, Common* common);
int RunView(const std::string& url, const Common& common);

void SetUpKeygen(CLI::App* cmd, Common* common);
int RunKeygen(const std::string& url, const Common& common);

}  // namespace viscera::client::cli
