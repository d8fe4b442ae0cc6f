#pragma once
// What an attacker on the bus sees and re-sends, for the end-to-end tests: every datagram of a
// channel as it was on the wire, and a process's memory.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "tests/e2e/e2e_harness.h"

namespace viscera::e2e {

// Every datagram on one channel, as it was on the wire.
class Capture {
 public:
  explicit Capture(const std::string& channel) : lcm_(kUrl) {
    EXPECT_TRUE(lcm_.good());
    lcm_.subscribeFunction(channel, &Capture::Keep, this);
  }
  // Takes what LCM queued meanwhile (its receive thread buffers while the test waits).
  const std::vector<std::vector<uint8_t>>& Drain(double quiet_s = 0.3) {
    while (lcm_.handleTimeout(static_cast<int>(quiet_s * 1000)) > 0) {
    }
    return datagrams_;
  }
  void Publish(const std::string& channel, const std::vector<uint8_t>& data) {
    lcm_.publish(channel, data.data(), static_cast<unsigned>(data.size()));
  }

 private:
  static void Keep(const lcm::ReceiveBuffer* rbuf, const std::string&, Capture* self) {
    const auto* p = static_cast<const uint8_t*>(rbuf->data);
    self->datagrams_.emplace_back(p, p + rbuf->data_size);
  }
  lcm::LCM lcm_;
  std::vector<std::vector<uint8_t>> datagrams_;
};

template <typename Msg>
inline std::optional<Msg> Decode(const std::vector<uint8_t>& d) {
  Msg m;
  if (m.decode(d.data(), 0, static_cast<int>(d.size())) != static_cast<int>(d.size()))
    return std::nullopt;
  return m;
}

// VmRSS of a process (kB).
inline int64_t RssKb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoll(line.substr(6));
  }
  return -1;
}

}  // namespace viscera::e2e
