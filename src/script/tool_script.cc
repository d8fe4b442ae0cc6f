#include "script/tool_script.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"
#include "script/csv_rows.h"

namespace viscera::script {
namespace {

// The point of the tube's surface over the centre-line point c, on the side facing p. On the
// surface, not the axis: jaws aimed at the axis would press the tube with the whole coupling
// force before they close. p itself when it is inside the tube.
Vec3 OntoSurface(const Tube& tube, const Vec3& c, const Vec3& p) {
  const double distance = (p - c).norm();
  if (distance <= tube.radius) return p;
  return c + (tube.radius / distance) * (p - c);
}

// The point of a polyline (not empty) nearest to p, how far along the line it lies, and the
// line's length (m).
struct LinePoint {
  Vec3 point;
  double along = 0.0, length = 0.0;
};
LinePoint NearestOnLine(const std::vector<Vec3>& line, const Vec3& p) {
  LinePoint best{line.front(), 0.0, 0.0};
  double best_d2 = (line.front() - p).squaredNorm();
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    const Vec3 d = line[i + 1] - line[i];
    const double len2 = d.squaredNorm();
    const double u = len2 > 0.0 ? std::clamp((p - line[i]).dot(d) / len2, 0.0, 1.0) : 0.0;
    const Vec3 q = line[i] + u * d;
    const double d2 = (q - p).squaredNorm();
    const double len = std::sqrt(len2);
    if (d2 < best_d2) best_d2 = d2, best.point = q, best.along = best.length + u * len;
    best.length += len;
  }
  return best;
}

}  // namespace

ToolScript ToolScript::Load(const std::string& path) {
  return Parse(ReadScriptFile(path, "tool script"), path);
}

ToolScript ToolScript::Parse(const std::string& text, const std::string& source) {
  static const char* kColumns[] = {"t",  "tool", "x",  "y",   "z",  "qw",
                                   "qx", "qy",   "qz", "jaw", "aim"};
  ToolScript script;
  bool header = false;
  size_t columns = 10;  // 11 with the optional aim column
  ForEachCsvRow(text, [&](int line_no, const std::vector<std::string>& cells) {
    if (!header) {
      ThrowUnless(cells.size() == 10 || cells.size() == 11, source, ":", line_no,
                  ": header must be t,tool,x,y,z,qw,qx,qy,qz,jaw[,aim]");
      columns = cells.size();
      for (size_t i = 0; i < columns; ++i) {
        ThrowUnless(cells[i] == kColumns[i], source, ":", line_no, ": column ", i + 1, " is \"",
                    cells[i], "\", expected \"", kColumns[i], "\"");
      }
      header = true;
      return;
    }
    ThrowUnless(cells.size() == columns, source, ":", line_no, ": expected ", columns,
                " columns, got ", cells.size());
    double v[10] = {};
    for (int i = 0; i < 10; ++i) {
      if (i == 1) continue;
      char* end = nullptr;
      v[i] = std::strtod(cells[i].c_str(), &end);
      ThrowUnless(!cells[i].empty() && end && *end == '\0' && std::isfinite(v[i]), source, ":",
                  line_no, ": ", kColumns[i], " = \"", cells[i], "\": expected a finite number");
    }
    const std::string& tool = cells[1];
    ThrowUnless(!tool.empty(), source, ":", line_no, ": empty tool name");
    ToolKeyframe k;
    k.t = v[0];
    k.tip = Vec3(v[2], v[3], v[4]);
    k.orientation = Eigen::Quaterniond(v[5], v[6], v[7], v[8]);
    ThrowUnless(k.orientation.norm() > 1e-9, source, ":", line_no,
                ": orientation must be a non-zero quaternion");
    k.orientation.normalize();
    k.jaw = v[9];
    ThrowUnless(k.jaw >= 0.0 && k.jaw <= 1.0, source, ":", line_no, ": jaw = ", k.jaw,
                ": expected 0..1");
    if (columns == 11) {
      const std::string& aim = cells[10];
      k.grasp = aim.rfind("grasp@", 0) == 0;
      k.at_tube = aim.rfind("tube", 0) == 0 || k.grasp;
      if (aim.rfind("tube@", 0) == 0 || k.grasp) {
        const size_t at = aim.find('@') + 1;
        char* end = nullptr;
        k.along = std::strtod(aim.c_str() + at, &end);
        ThrowUnless(aim.size() > at && end && *end == '\0' && k.along >= 0.0 && k.along <= 1.0,
                    source, ":", line_no, ": aim = \"", aim, "\": expected ", aim.substr(0, at),
                    "S with 0 <= S <= 1");
      } else if (aim == "offset") {
        k.offset = true;
        bool aimed = false;
        for (const ToolKeyframe& f : script.frames_[cells[1]]) aimed = aimed || f.at_tube;
        ThrowUnless(aimed, source, ":", line_no,
                    ": aim = \"offset\" needs an earlier row of the tool aimed at the tube");
      } else {
        ThrowUnless(aim.empty() || aim == "point" || aim == "tube", source, ":", line_no,
                    ": aim = \"", aim,
                    "\": expected \"point\", \"tube\", \"tube@S\", \"grasp@S\" or \"offset\"");
      }
      script.aims_at_tube_ = script.aims_at_tube_ || k.at_tube;
    }
    std::vector<ToolKeyframe>& frames = script.frames_[tool];
    ThrowUnless(frames.empty() || k.t >= frames.back().t, source, ":", line_no, ": t = ", k.t,
                " goes back in time for tool \"", tool, "\"");
    frames.push_back(k);
    script.duration_ = std::max(script.duration_, k.t);
  });
  ThrowUnless(header, source, ": empty tool script (no header)");
  return script;
}

std::vector<std::string> ToolScript::tools() const {
  std::vector<std::string> names;
  for (const auto& [name, frames] : frames_) names.push_back(name);
  return names;
}

Vec3 NearestOnTube(const Tube& tube, const Vec3& p) {
  if (tube.centre_line.empty()) return p;
  return OntoSurface(tube, NearestOnLine(tube.centre_line, p).point, p);
}

Vec3 AlongTube(const Tube& tube, double s, const Vec3& p) {
  const std::vector<Vec3>& line = tube.centre_line;
  if (line.empty()) return p;
  double total = 0.0;
  for (size_t i = 0; i + 1 < line.size(); ++i) total += (line[i + 1] - line[i]).norm();
  double left = std::clamp(s, 0.0, 1.0) * total;
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    const double len = (line[i + 1] - line[i]).norm();
    if (left <= len && len > 0.0)
      return OntoSurface(tube, line[i] + (left / len) * (line[i + 1] - line[i]), p);
    left -= len;
  }
  return OntoSurface(tube, line.back(), p);
}

double AlongTubeFrom(const Tube& tube, double s, const Vec3& p) {
  if (tube.centre_line.size() < 2) return 0.0;
  const LinePoint nearest = NearestOnLine(tube.centre_line, p);
  return std::abs(nearest.along - std::clamp(s, 0.0, 1.0) * nearest.length);
}

Vec3 AimOnTube(const Tube& tube, const ToolKeyframe& frame) {
  return std::isnan(frame.along) ? NearestOnTube(tube, frame.tip)
                                 : AlongTube(tube, frame.along, frame.tip);
}

ToolKeyframe Interpolate(const std::vector<ToolKeyframe>& f, double t) {
  if (t <= f.front().t) return f.front();
  if (t >= f.back().t) return f.back();
  const auto next = std::upper_bound(f.begin(), f.end(), t,
                                     [](double x, const ToolKeyframe& k) { return x < k.t; });
  const ToolKeyframe& b = *next;
  const ToolKeyframe& a = *(next - 1);
  const double span = b.t - a.t;
  const double u = span > 0.0 ? (t - a.t) / span : 1.0;
  ToolKeyframe k;
  k.t = t;
  k.tip = a.tip + u * (b.tip - a.tip);
  k.orientation = a.orientation.slerp(u, b.orientation);
  k.jaw = a.jaw + u * (b.jaw - a.jaw);
  return k;
}

}  // namespace viscera::script
