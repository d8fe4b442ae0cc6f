// viscera destroy, pause, resume, reset: one request with the session's token.
#include <cstdio>
#include <iostream>

#include "client/cli/commands.h"
#include "client/status_format.h"
#include "client/token_store.h"

namespace viscera::client::cli {

using viscera_proto::session_reply_t;
using viscera_proto::session_request_t;

namespace {

// one command runs per process: the four share the id they parse into
int64_t session_id = 0;

}  // namespace

int RunSessionRequest(const std::string& url, const Common& c, int8_t command, int64_t id,
                      const std::function<void(session_request_t*)>& fill) {
  std::string server_id;
  const std::vector<uint8_t> token = TokenFor(c, id, &server_id);
  SessionClient client(url, LoadAuth(c));
  session_request_t request = MakeRequest(command, id);
  request.header.token = token;
  request.header.token_len = static_cast<int32_t>(token.size());
  if (fill) fill(&request);
  const auto replies = client.Request(request, c.timeout_s);
  if (replies.empty()) return NoServer(c, url, "the request");
  const session_reply_t& reply = replies.front();
  if (const int rc = ReplyError(reply, id); rc != 0) return rc;
  if (command == session_request_t::kDestroy) {
    TokenStore store(c.sessions_file);
    store.Erase(id);
  }
  if (c.json) {
    Json j = {{"session", id}, {"server_id", reply.server_id}, {"ok", true}};
    if (reply.num_sessions > 0) j["status"] = StatusToJson(reply.sessions[0]);
    std::cout << j.dump(2) << "\n";
  } else if (reply.num_sessions > 0) {
    std::cout << StatusTable({reply.sessions[0]});
  } else {
    std::printf("ok\n");
  }
  return 0;
}

void SetUpSessionCommand(CLI::App* cmd, Common* common) {
  cmd->add_option("id", session_id, "Session id")->required();
  AddTokenOptions(cmd, common);
}

int RunDestroy(const std::string& url, const Common& c) {
  return RunSessionRequest(url, c, session_request_t::kDestroy, session_id);
}

int RunPause(const std::string& url, const Common& c) {
  return RunSessionRequest(url, c, session_request_t::kPause, session_id);
}

int RunResume(const std::string& url, const Common& c) {
  return RunSessionRequest(url, c, session_request_t::kResume, session_id);
}

int RunReset(const std::string& url, const Common& c) {
  return RunSessionRequest(url, c, session_request_t::kReset, session_id);
}

}  // namespace viscera::client::cli
