#include "client/gesture.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "common/check.h"

namespace viscera::client {

std::vector<Waypoint> ClearingGesture() {
  return {
      {0.0, Vec3(-0.25, 0.0, 0.15), 1.0},  // above, outside the coil
      {1.0, Vec3(-0.25, 0.0, 0.02), 1.0},  // down beside it
      {5.0, Vec3(0.25, 0.0, 0.02), 1.0},   // sweep through, pushing it aside
      {6.0, Vec3(0.25, 0.0, 0.15), 1.0},   // lift out
  };
}

std::vector<Waypoint> LoadScript(const std::string& path) {
  std::ifstream in(path);
  ThrowUnless(in.good(), "cannot read script '", path, "'");
  std::vector<Waypoint> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    Waypoint w;
    ThrowUnless(static_cast<bool>(fields >> w.t >> w.position.x() >> w.position.y() >> w.position.z()),
                path, ":", n, ": expected 't x y z [jaw]', got '", line, "'");
    if (!(fields >> w.jaw)) w.jaw = 1.0;
    ThrowUnless(std::isfinite(w.t) && w.position.allFinite() && w.jaw >= 0.0 && w.jaw <= 1.0, path,
                ":", n, ": values must be finite and jaw within [0, 1]");
    ThrowUnless(out.empty() || w.t > out.back().t, path, ":", n, ": time ", w.t,
                " does not increase");
    out.push_back(w);
  }
  ThrowUnless(!out.empty(), "script '", path, "' has no waypoints");
  return out;
}

Waypoint Sample(const std::vector<Waypoint>& path, double t) {
  VISCERA_DEMAND(!path.empty());
  if (t <= path.front().t) return path.front();
  for (size_t i = 1; i < path.size(); ++i) {
    if (t <= path[i].t) {
      const Waypoint& a = path[i - 1];
      const Waypoint& b = path[i];
      const double u = (t - a.t) / (b.t - a.t);
      return {t, a.position + u * (b.position - a.position), a.jaw + u * (b.jaw - a.jaw)};
    }
  }
  return path.back();
}

}  // namespace viscera::client
