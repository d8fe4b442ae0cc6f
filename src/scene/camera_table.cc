#include "scene/camera_table.h"

#include <toml++/toml.h>
#include <cmath>
#include <numbers>

#include "common/check.h"
#include "scene/toml_reader.h"

namespace viscera::scene {
namespace {

double InRange(const TomlReader& r, const char* key, double fallback, double lo, double hi) {
  const double value = r.Double(key, fallback);
  ThrowUnless(value >= lo && value <= hi, r.Name(key), " = ", value, ": must be in [", lo, ", ", hi,
              "]");
  return value;
}

}  // namespace

std::optional<mechanics::ScopeParams> ReadCamera(const toml::table& root) {
  const toml::node* node = root.get("camera");
  if (!node) return std::nullopt;
  ThrowUnless(node->is_table(), "camera: expected a table [camera]");
  const TomlReader r(*node->as_table(), "camera");
  mechanics::ScopeParams s;
  s.port = r.Vector("port");
  ThrowUnless(r.Has("look_at") != r.Has("direction"), r.Name("look_at"),
              ": give where the scope aims, look_at (a point) or direction (a vector), ",
              r.Has("look_at") ? "not both" : "one of them");
  Vec3 axis;
  if (r.Has("look_at")) {
    s.look_at = r.Vector("look_at");
    axis = s.look_at - s.port;
    ThrowUnless(axis.norm() > 1e-3, r.Name("look_at"), ": must be at least 1 mm from the port");
  } else {
    axis = r.Vector("direction");
    ThrowUnless(axis.norm() > 1e-9, r.Name("direction"), ": must not be zero");
    s.look_at = s.port + 0.1 * axis.normalized();
  }
  s.insertion = InRange(r, "insertion", s.insertion, 0.0, 0.5);
  s.optics_deg = InRange(r, "optics", s.optics_deg, 0.0, 60.0);
  s.roll_deg = InRange(r, "roll", s.roll_deg, -360.0, 360.0);
  s.fov_deg = InRange(r, "fov", s.fov_deg, 10.0, 120.0);
  s.light_range = InRange(r, "light_range", s.light_range, 1e-3, 10.0);
  s.light_cone_deg = InRange(r, "light_cone", s.light_cone_deg, 1.0, 90.0);
  const Vec3 up = r.Vector("up", s.up);
  ThrowUnless(up.norm() > 1e-9, r.Name("up"), ": must not be zero");
  s.up = up.normalized();
  // the line of sight is within `optics` of the shaft: keep the shaft that far (and 1 degree
  // more) from up, so the image always has an up
  const double from_up =
      std::acos(std::abs(axis.normalized().dot(s.up))) * 180.0 / std::numbers::pi;
  ThrowUnless(from_up > s.optics_deg + 1.0, r.Name("up"), ": the scope's shaft is ", from_up,
              " degrees from up (or down); with ", s.optics_deg,
              " degree optics it must be more than ", s.optics_deg + 1.0);
  r.Finish();
  return s;
}

}  // namespace viscera::scene
