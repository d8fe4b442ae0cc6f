#include "haptic/replay_device.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/check.h"

namespace viscera::haptic {

ReplayDevice ReplayDevice::Load(const std::string& path, DeviceLimits limits) {
  std::ifstream in(path);
  ThrowUnless(in.good(), "cannot read the replay log '", path, "'");
  std::ostringstream text;
  text << in.rdbuf();
  return Parse(text.str(), path, limits);
}

ReplayDevice ReplayDevice::Parse(const std::string& text, const std::string& source,
                                 DeviceLimits limits) {
  ReplayDevice d;
  d.limits_ = limits;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const std::exception& e) {
      Fail(source, ":", number, ": not JSON (", e.what(), ")");
    }
    ThrowUnless(j.is_object() && j.contains("t") && j["t"].is_number() && j.contains("position") &&
                    j["position"].is_array() && j["position"].size() == 3,
                source, ":", number, ": needs \"t\" (s) and \"position\" ([x, y, z], m)");
    Vec3 x;
    for (int a = 0; a < 3; ++a) {
      ThrowUnless(j["position"][a].is_number(), source, ":", number, ": position[", a,
                  "] is not a number");
      x(a) = j["position"][a].get<double>();
    }
    const double t = j["t"].get<double>();
    ThrowUnless(std::isfinite(t) && x.allFinite(), source, ":", number,
                ": non-finite t or position");
    ThrowUnless(d.t_.empty() || t >= d.t_.back(), source, ":", number, ": t = ", t,
                " s goes back in time (previous ", d.t_.empty() ? 0.0 : d.t_.back(), " s)");
    d.t_.push_back(t);
    d.x_.push_back(x);
  }
  ThrowUnless(!d.t_.empty(), source, ": no samples");
  const double t0 = d.t_.front();
  for (double& t : d.t_) t -= t0;
  return d;
}

DeviceSample ReplayDevice::Read(double t) {
  DeviceSample s;
  while (cursor_ + 1 < t_.size() && t_[cursor_ + 1] <= t) ++cursor_;
  if (cursor_ + 1 >= t_.size() || t <= t_[cursor_]) {
    s.position = x_[cursor_];
    return s;
  }
  const double span = t_[cursor_ + 1] - t_[cursor_];
  const double u = span > 0.0 ? (t - t_[cursor_]) / span : 1.0;
  s.position = (1.0 - u) * x_[cursor_] + u * x_[cursor_ + 1];
  return s;
}

}  // namespace viscera::haptic
