#pragma once
// A SessionManager on an in-process bus (memq): requests in, replies out, nothing thrown.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <viscera_proto/session_reply_t.hpp>
#include <viscera_proto/session_request_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "server/session_manager.h"

namespace viscera::server {

// The manager on an in-process bus: requests in, replies out, nothing thrown.
class SessionManagerTest : public ::testing::Test {
 protected:
  SessionManagerTest() : bus_("memq://") {
    config_.server_id = "srv";
    config_.scene_dir = std::string(VISCERA_SOURCE_DIR) + "/scenes";
    config_.max_sessions = 1;
    // The load limit times real steps, which sanitizer builds run 5-15x slower (hanging.toml came
    // out at 1.4 cores under TSan). These tests are not about it; its own test sets 1e-6.
    config_.max_session_load = 0.0;
    // The frame tests assert the size and rate they asked for, which a loaded machine would
    // have the governor lower (FrameGovernor has its own test).
    config_.adaptive_frames = false;
    manager_ = std::make_unique<SessionManager>(config_, &bus_, &bus_);  // memq: one bus
    bus_.Subscribe<viscera_proto::session_reply_t>(
        bus::kReplyChannel,
        [this](const viscera_proto::session_reply_t& r, int64_t) { replies_.push_back(r); });
  }

  viscera_proto::session_reply_t Ask(viscera_proto::session_request_t r) {
    return Deliver(Stamp(r));
  }

  /// `r` as this test's one client sends it: a new request_id, the next sequence number
  /// (replay protection), stamped now.
  viscera_proto::session_request_t Stamp(viscera_proto::session_request_t r) {
    r.header.version = viscera_proto::header_t::kProtocolVersion;
    r.header.utime = bus::WallMicros();
    r.request_id = ++request_id_;
    r.header.seq = request_id_;
    return r;
  }

  /// Hands `r` to the manager exactly as it is (a replay, a forged header) and returns the
  /// reply to its request_id.
  viscera_proto::session_reply_t Deliver(const viscera_proto::session_request_t& r) {
    const size_t before = replies_.size();
    const std::string channel = bus::kRequestChannel;
    manager_->OnRequest(r, bus::MessageInfo{&channel, 0, 0});
    // Up to 120 s, a deadline that a passing create never reaches: it was raised from 30 s when
    // the liver's distance field took ~21 s of CPU under ASan (brute force); since the triangle
    // hierarchy it takes ~2.3 s there (docs/testing.md says why the deadline stays).
    for (int i = 0; i < 24000 && manager_->creating(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      manager_->Poll();
    }
    bus_.Drain();
    EXPECT_GT(replies_.size(), before);
    if (replies_.size() <= before) return {};
    EXPECT_EQ(replies_.back().request_id, r.request_id);
    return replies_.back();
  }

  static viscera_proto::session_request_t Request(int8_t command, int64_t id = 0) {
    viscera_proto::session_request_t r{};
    r.header = bus::MakeHeader(id, 0);
    r.command = command;
    r.server_id = "srv";
    return r;
  }

  /// A new manager with `config` (the old one stops its sessions first).
  void Restart(const ServerConfig& config) {
    manager_.reset();
    config_ = config;
    manager_ = std::make_unique<SessionManager>(config_, &bus_, &bus_);
  }

  bus::LcmBus bus_;
  ServerConfig config_;
  std::unique_ptr<SessionManager> manager_;
  std::vector<viscera_proto::session_reply_t> replies_;
  int64_t request_id_ = 0;
};

}  // namespace viscera::server
