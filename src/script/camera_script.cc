#include "script/camera_script.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "common/check.h"
#include "script/csv_rows.h"

namespace viscera::script {

CameraScript CameraScript::Load(const std::string& path) {
  return Parse(ReadScriptFile(path, "camera script"), path);
}

CameraScript CameraScript::Parse(const std::string& text, const std::string& source) {
  static const char* kColumns[] = {"t", "ex", "ey", "ez", "cx", "cy", "cz"};
  CameraScript script;
  bool header = false;
  ForEachCsvRow(text, [&](int line_no, const std::vector<std::string>& cells) {
    ThrowUnless(cells.size() == 7, source, ":", line_no, ": expected 7 columns (",
                header ? "a row" : "the header t,ex,ey,ez,cx,cy,cz", "), got ", cells.size());
    if (!header) {
      for (size_t i = 0; i < 7; ++i) {
        ThrowUnless(cells[i] == kColumns[i], source, ":", line_no, ": column ", i + 1, " is \"",
                    cells[i], "\", expected \"", kColumns[i], "\"");
      }
      header = true;
      return;
    }
    double v[7] = {};
    for (int i = 0; i < 7; ++i) {
      char* end = nullptr;
      v[i] = std::strtod(cells[i].c_str(), &end);
      ThrowUnless(!cells[i].empty() && end && *end == '\0' && std::isfinite(v[i]), source, ":",
                  line_no, ": ", kColumns[i], " = \"", cells[i], "\": expected a finite number");
    }
    CameraKeyframe k{v[0], Vec3(v[1], v[2], v[3]), Vec3(v[4], v[5], v[6])};
    ThrowUnless(script.frames_.empty() || k.t >= script.frames_.back().t, source, ":", line_no,
                ": t = ", k.t, " comes before the row above");
    ThrowUnless((k.target - k.eye).norm() > 1e-6, source, ":", line_no,
                ": the lens is on the point it looks at");
    script.frames_.push_back(k);
  });
  ThrowUnless(header, source, ": empty camera script (header t,ex,ey,ez,cx,cy,cz)");
  ThrowUnless(!script.frames_.empty(), source, ": no camera rows");
  return script;
}

CameraKeyframe CameraScript::At(double t) const {
  if (t <= frames_.front().t) return frames_.front();
  if (t >= frames_.back().t) return frames_.back();
  const auto next = std::upper_bound(frames_.begin(), frames_.end(), t,
                                     [](double v, const CameraKeyframe& k) { return v < k.t; });
  const CameraKeyframe& b = *next;
  const CameraKeyframe& a = *(next - 1);
  const double u = b.t > a.t ? (t - a.t) / (b.t - a.t) : 1.0;
  return {t, a.eye + u * (b.eye - a.eye), a.target + u * (b.target - a.target)};
}

}  // namespace viscera::script
