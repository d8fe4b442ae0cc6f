#pragma once
/// LcmLink: ForceLink over the viscera protocol on an LcmBus: tool_pose_t on VISCERA_POSE_<id>
/// (with the session token), force_feedback_t from VISCERA_FORCE_<id> for one tool.
///
/// Threading: the device loop's thread owns the bus (it pumps it in Poll) and calls everything.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <viscera_proto/tool_pose_t.hpp>

#include "bus/lcm_bus.h"
#include "haptic/force_link.h"

namespace viscera::haptic {

class LcmLink : public ForceLink {
 public:
  /// @pre bus outlives the link; session_id > 0; tool >= 0.
  LcmLink(bus::LcmBus* bus, int64_t session_id, std::vector<uint8_t> token, int tool);
  ~LcmLink() override;
  LcmLink(const LcmLink&) = delete;
  LcmLink& operator=(const LcmLink&) = delete;

  void SendPose(int64_t seq, const DeviceSample& sample) override;
  void Poll(const Sink& sink) override;
  int64_t rejected() const override { return rejected_; }
  int64_t publish_failures() const { return publish_failures_; }

 private:
  bus::LcmBus* bus_;
  int64_t session_id_;
  std::vector<uint8_t> token_;
  int tool_;
  std::string pose_channel_;
  bus::SubscriptionId subscription_ = 0;
  viscera_proto::tool_pose_t pose_{};
  std::vector<std::pair<Answer, int64_t>> pending_;  // filled by the handler, drained by Poll
  int64_t wall_to_monotonic_ns_ = 0;                 // LCM stamps receive times on the wall clock
  int64_t rejected_ = 0, publish_failures_ = 0;
};

}  // namespace viscera::haptic
