// viscera list: the status of every session of every server that answers.
#include <algorithm>
#include <iostream>
#include <vector>

#include "client/cli/commands.h"
#include "client/status_format.h"

namespace viscera::client::cli {

using viscera_proto::session_request_t;

void SetUpList(CLI::App* cmd, Common* common) {
  (void)cmd;
  (void)common;
}

int RunList(const std::string& url, const Common& c) {
  SessionClient client(url, LoadAuth(c));
  const auto replies = client.Request(MakeRequest(session_request_t::kList, 0), c.timeout_s,
                                      /*collect_all=*/true, /*grace_s=*/0.5);
  if (replies.empty()) return NoServer(c, url, "the list request");
  std::vector<viscera_proto::session_status_t> all;
  for (const auto& r : replies) all.insert(all.end(), r.sessions.begin(), r.sessions.end());
  std::sort(all.begin(), all.end(),
            [](const auto& a, const auto& b) { return a.header.session_id < b.header.session_id; });
  if (c.json) {
    Json array = Json::array();
    for (const auto& s : all) array.push_back(StatusToJson(s));
    std::cout << array.dump(2) << "\n";
  } else {
    std::cout << StatusTable(all);
  }
  return 0;
}

}  // namespace viscera::client::cli
