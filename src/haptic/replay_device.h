#pragma once
/// ReplayDevice: positions from a recorded log, one JSON object per line with at least `t` (s)
/// and `position` ([x, y, z], m): the `viscera haptic --log` format, so a session recorded
/// with any device (the sim hand, a real one) can be played again. Between samples the
/// position is interpolated linearly; after the last it holds. It feels nothing: the forces
/// written are kept only as the last one (a log is an open loop).
#include <string>
#include <vector>

#include "haptic/device.h"

namespace viscera::haptic {

class ReplayDevice : public Device {
 public:
  /// @throws InputError naming the file and line for anything malformed (not JSON, no t or
  ///         position, non-finite values, t going backwards) or when it has no sample.
  static ReplayDevice Load(const std::string& path, DeviceLimits limits = {});
  /// Same from the text of a log.
  static ReplayDevice Parse(const std::string& text, const std::string& source,
                            DeviceLimits limits = {});

  DeviceLimits limits() const override { return limits_; }
  DeviceSample Read(double t) override;
  void Write(const Vec3& force) override { last_force_ = force; }
  double duration() const override { return t_.back() - t_.front(); }
  const char* name() const override { return "replay"; }
  const Vec3& last_force() const { return last_force_; }

 private:
  ReplayDevice() = default;
  DeviceLimits limits_;
  std::vector<double> t_;  // s, from the log's first sample
  std::vector<Vec3> x_;    // m
  size_t cursor_ = 0;      // reads go forward: the segment of the last read
  Vec3 last_force_ = Vec3::Zero();
};

}  // namespace viscera::haptic
