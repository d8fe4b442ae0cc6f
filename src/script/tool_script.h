#pragma once
/// Scripted tool trajectories: a CSV with the header `t,tool,x,y,z,qw,qx,qy,qz,jaw` (seconds,
/// tool name, target tip position in m, orientation quaternion, jaw opening 0 = closed ..
/// 1 = open), one keyframe per row, and an optional last column `aim`: `point` (the default),
/// `tube`, which aims the row at the tube itself: its target is the point of the tube's surface
/// nearest to the row's position, or `tube@S` (0 <= S <= 1), which aims it at one part of the
/// bowel: the tube's surface at arc-length fraction S of its centre line, on the side facing
/// the row's position, `grasp@S`: aimed as `tube@S`, and the tool arrives there before it goes
/// on: when the row is due and the part of the tube nearest the jaws is not that part (more than
/// a tube's diameter away along the centre line), the tool backs off and reaches again
/// (ScriptPlayer), or `offset`: the row's x, y, z are an offset from where the tool's last
/// row aimed at the tube landed (lift what was grasped, whatever the pile). `tube` still depends on
/// where the pile settled (the nearest loop to a fixed point); `tube@S` takes the same piece of
/// bowel whatever the pile (ScriptPlayer resolves both). Between rows of a tool the target is
/// interpolated (linearly, orientation by slerp); before its first row it holds the first, after
/// its last the last.
#include <limits>
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
  bool at_tube = false;  ///< aim at the tube: `along` or, if NaN, the surface point nearest `tip`
  double along = std::numeric_limits<double>::quiet_NaN();  ///< aim: the arc-length fraction S
  /// aim = offset: `tip` is an offset from where the tool's last row aimed at the tube landed
  bool offset = false;
  /// aim = grasp@S: the jaws must be at that part of the tube before the tool goes on
  bool grasp = false;
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

/// The point of the tube's surface at arc-length fraction s (clamped to 0..1) of its centre
/// line, on the side facing p (p itself when the centre line is empty).
Vec3 AlongTube(const Tube& tube, double s, const Vec3& p);

/// How far along the centre line (m) the part of the tube nearest to p is from the part at
/// arc-length fraction s (0 when the centre line has fewer than two points).
double AlongTubeFrom(const Tube& tube, double s, const Vec3& p);

/// Where a row aimed at the tube lands (`frame.at_tube`): AlongTube or NearestOnTube.
Vec3 AimOnTube(const Tube& tube, const ToolKeyframe& frame);

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
  const std::vector<ToolKeyframe>& frames(const std::string& tool) const {
    return frames_.at(tool);
  }
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
