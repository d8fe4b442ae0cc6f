// The Python types that lcm-gen writes for scripts must agree with the C++ ones: a
// heartbeat encoded by Python decodes in C++ with every field intact.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

namespace {

std::vector<uint8_t> RunPython(const std::string& script) {
  const std::string command = "PYTHONPATH='" VISCERA_PYTHON_DIR "' python3 -c \"" + script + "\"";
  FILE* pipe = popen(command.c_str(), "r");
  EXPECT_NE(pipe, nullptr);
  std::vector<uint8_t> out;
  if (pipe == nullptr) return out;
  for (int c = std::fgetc(pipe); c != EOF; c = std::fgetc(pipe))
    out.push_back(static_cast<uint8_t>(c));
  EXPECT_EQ(pclose(pipe), 0) << command;
  return out;
}

TEST(PythonInterop, HeartbeatEncodedByPythonDecodesInCpp) {
  // lcm-gen 1.3.1's Python defaults byte arrays to "" (a str on Python 3): set bytes.
  const std::vector<uint8_t> bytes = RunPython(
      "import sys; from viscera_proto import heartbeat_t, header_t\n"
      "m = heartbeat_t(); h = header_t()\n"
      "h.version = header_t.kProtocolVersion; h.session_id = 0; h.seq = 41; h.utime = "
      "1700000000000000\n"
      "h.token = bytes([1, 2, 3]); h.token_len = 3; h.mac = b''; h.mac_len = 0; m.header = h\n"
      "m.server_id = 'py'; m.num_sessions = 2; m.max_sessions = 9; m.load = 0.5; m.uptime_us = 77\n"
      "m.rejected = 5\n"
      "sys.stdout.buffer.write(m.encode())");
  viscera_proto::heartbeat_t msg;
  ASSERT_EQ(msg.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  EXPECT_EQ(msg.header.version, viscera_proto::header_t::kProtocolVersion);
  EXPECT_EQ(msg.header.seq, 41);
  EXPECT_EQ(msg.header.utime, 1700000000000000);
  EXPECT_EQ(msg.header.token, (std::vector<uint8_t>{1, 2, 3}));
  EXPECT_EQ(msg.server_id, "py");
  EXPECT_EQ(msg.num_sessions, 2);
  EXPECT_EQ(msg.max_sessions, 9);
  EXPECT_EQ(msg.load, 0.5f);
  EXPECT_EQ(msg.uptime_us, 77);
  EXPECT_EQ(msg.rejected, 5);
}

TEST(PythonInterop, ToolPoseEncodedByPythonDecodesInCpp) {
  // what a Python device bridge or load-testing script sends
  const std::vector<uint8_t> bytes = RunPython(
      "import sys; from viscera_proto import tool_pose_t, header_t\n"
      "p = tool_pose_t(); h = header_t()\n"
      "h.version = header_t.kProtocolVersion; h.session_id = 99; h.seq = 5; h.utime = 17\n"
      "h.token = bytes(range(16)); h.token_len = 16; h.mac = b''; h.mac_len = 0; p.header = h\n"
      "p.tool = 1; p.position = [0.1, -0.2, 0.3]; p.orientation = [1.0, 0.0, 0.0, 0.0]; p.jaw = "
      "0.25\n"
      "sys.stdout.buffer.write(p.encode())");
  viscera_proto::tool_pose_t msg;
  ASSERT_EQ(msg.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  EXPECT_EQ(msg.header.session_id, 99);
  EXPECT_EQ(msg.header.token.size(), 16u);
  EXPECT_EQ(msg.header.token[15], 15);
  EXPECT_EQ(msg.tool, 1);
  EXPECT_EQ(msg.position[1], -0.2);
  EXPECT_EQ(msg.orientation[0], 1.0);
  EXPECT_EQ(msg.jaw, 0.25);
}

}  // namespace
