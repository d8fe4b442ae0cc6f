#include "haptic/lcm_link.h"

#include <viscera_proto/force_feedback_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/tool_pose.h"
#include "common/check.h"
#include "common/clock.h"

namespace viscera::haptic {

LcmLink::LcmLink(bus::LcmBus* bus, int64_t session_id, std::vector<uint8_t> token, int tool)
    : bus_(bus),
      session_id_(session_id),
      token_(std::move(token)),
      tool_(tool),
      pose_channel_(bus::SessionChannel(bus::kPosePrefix, session_id)) {
  VISCERA_DEMAND(bus_ != nullptr && session_id_ > 0 && tool_ >= 0);
  wall_to_monotonic_ns_ = MonotonicNanos() - bus::WallMicros() * 1000;
  pending_.reserve(256);
  subscription_ = bus_->Subscribe<viscera_proto::force_feedback_t>(
      bus::SessionChannel(bus::kForcePrefix, session_id),
      [this](const viscera_proto::force_feedback_t& f, int64_t recv_utime) {
        if (f.tool != tool_) return;  // another tool of the session: not ours, not an error
        if (f.header.session_id != session_id_ || !bus::HeaderProblem(f.header).empty()) {
          ++rejected_;
          return;
        }
        Answer a;
        a.seq = f.header.seq;
        a.step = f.step;
        a.pose_seq = f.pose_seq;
        a.grasping = f.grasping;
        for (int r = 0; r < 3; ++r) {
          a.force(r) = f.force[r];
          for (int c = 0; c < 3; ++c) a.stiffness(r, c) = f.stiffness[r][c];
        }
        pending_.emplace_back(a, recv_utime * 1000 + wall_to_monotonic_ns_);
      });
}

LcmLink::~LcmLink() { bus_->Unsubscribe(subscription_); }

void LcmLink::SendPose(int64_t seq, const DeviceSample& sample) {
  bus::FillToolPose(session_id_, seq, token_, tool_, sample.position, sample.orientation,
                    sample.jaw, &pose_);
  if (!bus_->Publish(pose_channel_, pose_)) ++publish_failures_;
}

void LcmLink::Poll(const Sink& sink) {
  bus_->Drain();
  for (const auto& [answer, arrived] : pending_) sink(answer, arrived);
  pending_.clear();
}

}  // namespace viscera::haptic
