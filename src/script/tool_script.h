#pragma once
/// Scripted tool trajectories: a CSV with the header `t,tool,x,y,z,qw,qx,qy,qz,jaw` (seconds,
/// tool name, target tip position in m, orientation quaternion, jaw opening 0 = closed ..
/// 1 = open), one keyframe per row. Between rows of a tool the target is interpolated (linearly,
/// orientation by slerp); before its first row it holds the first, after its last the last.
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/types.h"

namespace viscera::script {

struct ToolKeyframe {
  double t = 0.0;
  Vec3 tip = Vec3::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  double jaw = 1.0;
};

class ToolScript {
 public:
  /// @throws InputError naming the file, line and column for anything malformed.
  static ToolScript Load(const std::string& path);
  static ToolScript Parse(const std::string& text, const std::string& source = "<script>");

  bool Has(const std::string& tool) const { return frames_.count(tool) > 0; }
  std::vector<std::string> tools() const;
  /// The interpolated target of `tool` at time t. @pre Has(tool).
  ToolKeyframe At(const std::string& tool, double t) const;
  /// Time of the last keyframe over all tools (s).
  double duration() const { return duration_; }

 private:
  std::map<std::string, std::vector<ToolKeyframe>> frames_;
  double duration_ = 0.0;
};

}  // namespace viscera::script
