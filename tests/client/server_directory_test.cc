#include "client/server_directory.h"

#include <gtest/gtest.h>

#include "bus/header.h"

namespace viscera::client {
namespace {

viscera_proto::heartbeat_t Beat(const std::string& id, int sessions, float load, int64_t seq) {
  viscera_proto::heartbeat_t msg;
  msg.header = bus::MakeHeader(0, seq);
  msg.server_id = id;
  msg.num_sessions = sessions;
  msg.max_sessions = 4;
  msg.load = load;
  msg.uptime_us = 2'500'000;
  msg.cores = 2;
  msg.not_ours = 0;
  msg.unconverged_solves = 0;
  msg.capacity = "";
  return msg;
}

TEST(ServerDirectory, KeepsTheLatestHeartbeatPerServerSortedById) {
  ServerDirectory directory;
  directory.Observe(Beat("beta", 1, 0.5f, 0));
  directory.Observe(Beat("alpha", 0, 0.25f, 0));
  directory.Observe(Beat("beta", 3, 0.75f, 1));
  const auto servers = directory.Servers();
  ASSERT_EQ(servers.size(), 2u);
  EXPECT_EQ(servers[0].server_id, "alpha");
  EXPECT_EQ(servers[1].server_id, "beta");
  EXPECT_EQ(servers[1].sessions, 3);
  EXPECT_DOUBLE_EQ(servers[1].load, 0.75);
  EXPECT_EQ(servers[1].heartbeats, 2);
  EXPECT_DOUBLE_EQ(servers[1].uptime_s, 2.5);
}

TEST(ServerDirectory, RejectsHeartbeatsItCannotTrust) {
  ServerDirectory directory;
  viscera_proto::heartbeat_t other_version = Beat("x", 0, 0.0f, 0);
  other_version.header.version = viscera_proto::header_t::kProtocolVersion + 1;
  directory.Observe(other_version);
  directory.Observe(Beat("", 0, 0.0f, 0));
  EXPECT_TRUE(directory.Servers().empty());
  EXPECT_EQ(directory.rejected(), 2);
  EXPECT_EQ(directory.last_rejection(), "empty server id");
}

TEST(ServerDirectory, JsonAndTableListEveryServer) {
  ServerDirectory directory;
  viscera_proto::heartbeat_t alpha = Beat("alpha", 1, 0.5f, 0);
  alpha.capacity = "max 4 sessions: --max-sessions";
  alpha.not_ours = 7;
  alpha.unconverged_solves = 5'000'000'000;  // beyond 32 bits
  directory.Observe(alpha);
  directory.Observe(Beat("a-much-longer-server-name", 2, 0.125f, 0));
  const auto servers = directory.Servers();
  const nlohmann::ordered_json json = ServersToJson(servers);
  ASSERT_TRUE(json.is_array());
  ASSERT_EQ(json.size(), 2u);
  EXPECT_EQ(json[1]["server_id"], "alpha");
  EXPECT_EQ(json[1]["sessions"], 1);
  EXPECT_EQ(json[1]["max_sessions"], 4);
  EXPECT_DOUBLE_EQ(json[1]["load"].get<double>(), 0.5);
  EXPECT_EQ(json[1]["not_ours"], 7);
  EXPECT_EQ(json[1]["unconverged_solves"], 5'000'000'000);
  EXPECT_EQ(json[0]["unconverged_solves"], 0);
  EXPECT_EQ(json[1]["cores"], 2);
  EXPECT_EQ(json[1]["capacity"], "max 4 sessions: --max-sessions");

  const std::string table = ServersToTable(servers);
  EXPECT_EQ(table.rfind("SERVER", 0), 0u);
  EXPECT_NE(table.find("\nalpha "), std::string::npos) << table;
  EXPECT_NE(table.find("1/4"), std::string::npos) << table;
  EXPECT_NE(table.find("50%"), std::string::npos) << table;
  // why each server holds what it holds, under the table
  EXPECT_NE(table.find("\nalpha: max 4 sessions: --max-sessions\n"), std::string::npos) << table;
}

}  // namespace
}  // namespace viscera::client
