#include "client/cli/common.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "client/token_store.h"
#include "common/check.h"

namespace viscera::client::cli {

using viscera_proto::session_reply_t;
using viscera_proto::session_request_t;

void AddTokenOptions(CLI::App* cmd, Common* common) {
  // a session token: --token-file or $VISCERA_TOKEN (default: from --sessions); --token is
  // kept only to say why it is refused
  cmd->add_option(
      "--token-file", common->token_file,
      "File holding the session token (hex; or $VISCERA_TOKEN; default: from --sessions)");
  cmd->add_option("--token", common->token_hex, "Refused: use --token-file or $VISCERA_TOKEN")
      ->group("");
}

std::shared_ptr<const bus::MessageAuth> LoadAuth(const Common& c) {
  if (c.key_file.empty()) return nullptr;
  return std::make_shared<bus::MessageAuth>(bus::MessageAuth::FromKeyFile(c.key_file));
}

int NoServer(const Common& c, const std::string& url, const char* what) {
  std::fprintf(stderr,
               "viscera: no server answered %s on %s within %g s (is viscerad running? for "
               "udpm://, does this network have a multicast route?%s)\n",
               what, url.c_str(), c.timeout_s,
               c.key_file.empty() ? "" : " does the server use the same --key-file?");
  return kNoServer;
}

int ReplyError(const session_reply_t& reply, int64_t id) {
  switch (reply.result) {
    case session_reply_t::kOk: return 0;
    case session_reply_t::kUnknownSession:
      std::fprintf(stderr, "viscera: unknown session %lld\n", static_cast<long long>(id));
      return kUnknownSession;
    case session_reply_t::kBadToken:
      std::fprintf(
          stderr,
          "viscera: server %s refused: %s (this client has no valid token for session %lld)\n",
          reply.server_id.c_str(), reply.message.c_str(), static_cast<long long>(id));
      return kRefused;
    case session_reply_t::kReplayed:
      std::fprintf(stderr,
                   "viscera: server %s refused this command as replayed or stale: %s (nothing "
                   "changed; send it again)\n",
                   reply.server_id.c_str(), reply.message.c_str());
      return kRefused;
    default:
      std::fprintf(stderr, "viscera: server %s refused: %s\n", reply.server_id.c_str(),
                   reply.message.c_str());
      return kRefused;
  }
}

std::vector<uint8_t> TokenFor(const Common& c, int64_t id, std::string* server_id) {
  // a token from a file or the environment, never from argv (/proc/PID/cmdline)
  if (!c.token_file.empty()) {
    std::ifstream in(c.token_file);
    std::string hex;
    ThrowUnless(static_cast<bool>(in >> hex), "cannot read a token from '", c.token_file, "'");
    return FromHex(hex);
  }
  if (const char* env = std::getenv("VISCERA_TOKEN"); env != nullptr && env[0] != '\0') {
    return FromHex(env);
  }
  TokenStore store(c.sessions_file);
  const StoredSession* s = store.Find(id);
  if (s == nullptr) return {};
  if (server_id != nullptr) *server_id = s->server_id;
  return s->token;
}

int FetchStatus(SessionClient& client, const std::string& url, const Common& c, int64_t id,
                viscera_proto::session_status_t* out) {
  const auto replies = client.Request(MakeRequest(session_request_t::kStatus, id), c.timeout_s);
  if (replies.empty()) return NoServer(c, url, "the status request");
  if (const int rc = ReplyError(replies.front(), id); rc != 0) return rc;
  if (replies.front().num_sessions < 1) return kRefused;
  *out = replies.front().sessions[0];
  return 0;
}

}  // namespace viscera::client::cli
