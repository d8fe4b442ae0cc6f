#pragma once
// Drives a session's tools with a tool script, in-process, the way `viscera drive` does over the
// bus: each call posts every scripted tool's target at the simulated time of the session's latest
// snapshot plus one step, rows aimed at the tube resolved against that snapshot's sphere chain.
#include <memory>
#include <string>
#include <utility>

#include "collision/sphere_chain.h"
#include "common/clock.h"
#include "script/script_player.h"
#include "session/session.h"

namespace viscera::session::testing {

class ScriptDriver {
 public:
  /// @pre session outlives the driver; every tool of the script is one of the session's.
  ScriptDriver(Session* session, script::ToolScript script)
      : session_(session),
        player_(std::move(script)),
        chain_(session->model().curve(), session->model().params().length,
               session->model().params().radius) {}

  /// Posts the targets for the latest snapshot; false before the first snapshot.
  bool Post() {
    const std::shared_ptr<const Snapshot> snapshot = session_->LatestSnapshot();
    if (snapshot == nullptr) return false;
    tube_.centre_line.clear();
    if (player_.script().aims_at_tube()) {
      chain_.Place(snapshot->q);
      for (const collision::Sphere& s : chain_.spheres()) tube_.centre_line.push_back(s.centre);
      tube_.radius = chain_.radius();
    }
    const mechanics::ModelParams& params = session_->model().params();
    const double t = snapshot->t + 1.0 / params.rate_hz;
    for (size_t i = 0; i < params.tools.size(); ++i) {
      if (!player_.script().Has(params.tools[i].name)) continue;
      const script::ToolKeyframe k = player_.At(params.tools[i].name, t, tube_);
      PoseInput pose;
      pose.target.tip = k.tip;
      pose.target.orientation = k.orientation;
      pose.target.jaw = k.jaw;
      pose.seq = seq_++;
      pose.client_utime = pose.seq;
      pose.received_ns = MonotonicNanos();
      if (session_->inbox().PostPose(static_cast<int>(i), pose)) session_->CountPose();
    }
    return true;
  }

 private:
  Session* session_;
  script::ScriptPlayer player_;
  collision::SphereChain chain_;
  script::Tube tube_;
  int64_t seq_ = 0;
};

}  // namespace viscera::session::testing
