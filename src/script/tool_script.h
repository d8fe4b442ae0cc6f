#pragma once
/// Scripted tool trajectories: a CSV with the header `t,tool,x,y,z,qw,qx,qy,qz,jaw` (seconds,
/// tool name, target tip position in m, orientation quaternion, jaw opening 0 = closed ..
/// 1 = open), one keyframe per row, and an optional last column `aim`: `point` (the default) or
/// `tube`, which aims the row at the tube itself: its target is the point of the tube's surface
/// nearest to the row's position, so a gesture still finds its loop when the pile settled
/// elsewhere (ScriptPlayer resolves it). Between rows of a tool the target is interpolated
/// (linearly, orientation by slerp); before its first row it holds the first, after its last the
/// last.
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
  bool at_tube = false;  ///< aim: the nearest point of the tube's surface to `tip`
};

/// The tube as a script aims at it: its centre line (e.g. the sphere centres, in order) and
/// radius (m).
struct Tube {
  std::vector<Vec3> centre_line;
  double radius = 0.0;
};

/// The point of the tube's surface nearest to p (p itself inside the tube or when the centre
/// line is empty): the nearest point of the polyline, pushed out by the radius toward p.
Vec3 NearestOnTube(const Tube& tube, const Vec3& p);

/// The target at time t between keyframes (sorted by t, at least one).
ToolKeyframe Interpolate(const std::vector<ToolKeyframe>& frames, double t);

class ToolScript {
 public:
  /// @throws InputError naming the file, line and column for anything malformed.
  static ToolScript Load(const std::string& path);
  static ToolScript Parse(const std::string& text, const std::string& source = "<script>");

  bool Has(const std::string& tool) const { return frames_.count(tool) > 0; }
  std::vector<std::string> tools() const;
  /// The interpolated target of `tool` at time t, every row at its written position (aims
  /// unresolved: see ScriptPlayer). @pre Has(tool).
  ToolKeyframe At(const std::string& tool, double t) const { return Interpolate(frames(tool), t); }
  /// A tool's rows, in time order. @pre Has(tool).
  const std::vector<ToolKeyframe>& frames(const std::string& tool) const { return frames_.at(tool); }
  /// Whether some row aims at the tube (the caller then needs its centre line).
  bool aims_at_tube() const { return aims_at_tube_; }
  /// Time of the last keyframe over all tools (s).
  double duration() const { return duration_; }

 private:
  std::map<std::string, std::vector<ToolKeyframe>> frames_;
  double duration_ = 0.0;
  bool aims_at_tube_ = false;
};

}  // namespace viscera::script
