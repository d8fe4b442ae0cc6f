#pragma once
/// A scripted laparoscope: a CSV with the header `t,ex,ey,ez,cx,cy,cz` (seconds, the lens's
/// position and the point it looks at, in m), one keyframe per row in time order. Between rows
/// both points are interpolated linearly; before the first row the camera holds it, after the
/// last the last. viscera-sim moves its camera along one (`--camera-script`), so that what a run
/// shows and the time its tools spend out of view follow the camera a trainee would hold.
#include <string>
#include <vector>

#include "common/types.h"

namespace viscera::script {

struct CameraKeyframe {
  double t = 0.0;
  Vec3 eye = Vec3::Zero(), target = Vec3::Zero();
};

class CameraScript {
 public:
  /// @throws InputError naming the file and line for anything malformed: a bad header, a cell
  /// that is not a finite number, rows out of time order, a lens on the point it looks at.
  static CameraScript Load(const std::string& path);
  static CameraScript Parse(const std::string& text, const std::string& source = "<camera>");

  /// The camera at time t.
  CameraKeyframe At(double t) const;
  const std::vector<CameraKeyframe>& frames() const { return frames_; }

 private:
  std::vector<CameraKeyframe> frames_;
};

}  // namespace viscera::script
