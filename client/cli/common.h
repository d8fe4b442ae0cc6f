#pragma once
/// What every `viscera` command shares: the common options, the exit codes, the key, the
/// session token and the messages for a server that does not answer or refuses.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <viscera_proto/session_reply_t.hpp>
#include <viscera_proto/session_status_t.hpp>

#include "bus/message_auth.h"
#include "client/session_client.h"

namespace viscera::client::cli {

using Json = nlohmann::ordered_json;

// Exit codes: 0 success, 1 local error (bad URL, no multicast route, bad file), 2 no
// server answered, 3 unknown session, 4 the server refused (or bad token, bad request);
// CLI11 reports bad flags with its own codes (100 and up).
constexpr int kLocalError = 1;
constexpr int kNoServer = 2;
constexpr int kUnknownSession = 3;
constexpr int kRefused = 4;

/// The options of `viscera` itself, matched from any command.
struct Common {
  std::string lcm_url;
  std::string key_file;
  std::string sessions_file;
  std::string token_hex;   ///< --token: refused (argv is readable by every local user)
  std::string token_file;  ///< --token-file: the session token (hex) in a file
  double timeout_s = 2.0;
  bool json = false;
};

/// Adds --token-file (and the refused --token) to a command that needs a session token.
void AddTokenOptions(CLI::App* cmd, Common* common);

/// The key of --key-file, or nullptr without one.
std::shared_ptr<const bus::MessageAuth> LoadAuth(const Common& c);

/// Says that no server answered `what` on `url`; returns kNoServer.
int NoServer(const Common& c, const std::string& url, const char* what);

/// Exit code and message for a reply that is not kOk (0 for kOk).
int ReplyError(const viscera_proto::session_reply_t& reply, int64_t id);

/// Session `id`'s token: from --token-file, $VISCERA_TOKEN or the --sessions store (which
/// also names its server in *server_id, when not nullptr); empty when there is none.
std::vector<uint8_t> TokenFor(const Common& c, int64_t id, std::string* server_id);

/// Asks for one session's status: 0 with the status in *out, or the exit code to return.
int FetchStatus(SessionClient& client, const std::string& url, const Common& c, int64_t id,
                viscera_proto::session_status_t* out);

}  // namespace viscera::client::cli
