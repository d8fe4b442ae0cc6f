#include "server/frame_governor.h"

namespace viscera::server {

bool FrameGovernor::Update(const FrameCost& cost, double period_ms, double step_slack) {
  // overloaded: the frame alone takes most of a period, or it made the stream late
  const bool overloaded = cost.cpu_ms > config_.busy_high * period_ms || cost.wall_ms > period_ms ||
                          step_slack < config_.slack_low;
  // calm: this frame would have fitted comfortably in the period of the level above
  const int above = level_ > 0 ? level_ - 1 : 0;
  const double above_period_ms = period_ms * kFrameLevels[level_].rate / kFrameLevels[above].rate;
  const double scale_ratio = kFrameLevels[above].scale / kFrameLevels[level_].scale;
  const double pixels_ratio = scale_ratio * scale_ratio;  // cost ~ pixels
  const bool calm = cost.cpu_ms * pixels_ratio < config_.busy_low * above_period_ms &&
                    cost.wall_ms * pixels_ratio < config_.busy_high * above_period_ms &&
                    step_slack > config_.slack_high;
  overloaded_ = overloaded ? overloaded_ + 1 : 0;
  calm_ = calm ? calm_ + 1 : 0;
  const int last = static_cast<int>(kFrameLevels.size()) - 1;
  if (overloaded_ >= config_.overloaded_to_lower && level_ < last) {
    ++level_;
    overloaded_ = calm_ = 0;
    return true;
  }
  if (calm_ >= config_.calm_to_raise && level_ > 0) {
    --level_;
    overloaded_ = calm_ = 0;
    return true;
  }
  return false;
}

}  // namespace viscera::server
