#include "scene/task_reader.h"

#include <toml++/toml.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "assessment/target_samples.h"
#include "common/check.h"
#include "scene/toml_reader.h"

namespace viscera::scene {
namespace {

mechanics::TargetParams ReadTarget(const TomlReader& r, const mechanics::ModelParams& p) {
  mechanics::TargetParams t;
  t.name = r.String("name");
  ThrowUnless(!t.name.empty() && t.name.size() <= 32 &&
                  std::all_of(t.name.begin(), t.name.end(),
                              [](char ch) {
                                return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' ||
                                       ch == '-';
                              }),
              r.Name("name"), " = \"", t.name, "\": use 1 to 32 letters, digits, '_' or '-'");
  for (const mechanics::TargetParams& other : p.task.targets) {
    ThrowUnless(other.name != t.name, r.Name("name"), " = \"", t.name,
                "\": two targets share this name");
  }
  t.samples = r.Int("samples", t.samples);
  ThrowUnless(t.samples >= 1 && t.samples <= kMaxTargetSamples, r.Name("samples"), " = ", t.samples,
              ": must be in [1, ", kMaxTargetSamples, "]");
  const bool disc = r.Has("radius"), polygon = r.Has("polygon");
  ThrowUnless(disc != polygon, r.Name("radius"),
              ": give a disc (centre, normal, radius) or a polygon, ",
              disc ? "not both" : "one of them");
  if (disc) {
    t.centre = r.Vector("centre");
    t.radius = r.Double("radius");
    ThrowUnless(t.radius > 0.0, r.Name("radius"), " = ", t.radius, ": must be > 0");
    const Vec3 n = r.Vector("normal");
    ThrowUnless(n.norm() > 1e-9, r.Name("normal"), ": must not be zero");
    t.normal = n.normalized();
  } else {
    const Points corners = r.PointList("polygon");
    ThrowUnless(corners.rows() >= 3, r.Name("polygon"), ": needs at least 3 corners, has ",
                corners.rows());
    for (int i = 0; i < corners.rows(); ++i) t.polygon.push_back(corners.row(i).transpose());
    t.centre = corners.colwise().mean().transpose();
    Vec3 n = assessment::PolygonNormal(t.polygon);
    ThrowUnless(n.norm() > 0.5, r.Name("polygon"), ": its corners enclose no area");
    double off_plane = 0.0;
    for (const Vec3& c : t.polygon)
      off_plane = std::max(off_plane, std::abs((c - t.centre).dot(n)));
    const double size = std::sqrt(assessment::PolygonArea(t.polygon));
    ThrowUnless(off_plane <= 0.01 * size, r.Name("polygon"), ": corners are ", off_plane,
                " m off their plane (more than 1 % of the patch's size): a target is planar");
    // the side it is seen from: `normal` if given, else the corners' order (counter-clockwise)
    if (r.Has("normal") && r.Vector("normal").dot(n) < 0.0) n = -n;
    t.normal = n;
  }
  return t;
}

}  // namespace

void ReadTask(const std::vector<const toml::table*>& targets, const toml::table* assessment,
              mechanics::ModelParams* p) {
  ThrowUnless(static_cast<int>(targets.size()) <= kMaxTargets, "target: ", targets.size(),
              " targets, at most ", kMaxTargets);
  int index = 0;
  for (const toml::table* t : targets) {
    const TomlReader r(*t, "target[" + std::to_string(index++) + "]");
    mechanics::TargetParams target = ReadTarget(r, *p);
    r.Finish();
    p->task.targets.push_back(std::move(target));
  }
  if (assessment == nullptr) return;
  const TomlReader r(*assessment, "assessment");
  mechanics::AssessmentParams& a = p->task.assessment;
  a.traction_force = r.Positive("traction_force", a.traction_force);
  a.traction_hold = r.Positive("traction_hold", a.traction_hold);
  a.regrasp_window = r.NonNegative("regrasp_window", a.regrasp_window);
  a.exposed_fraction = r.Double("exposed_fraction", a.exposed_fraction);
  ThrowUnless(a.exposed_fraction > 0.0 && a.exposed_fraction <= 1.0, r.Name("exposed_fraction"),
              " = ", a.exposed_fraction, ": must be in (0, 1]");
  a.exposure_rate_hz = r.Positive("exposure_rate", a.exposure_rate_hz);
  ThrowUnless(a.exposure_rate_hz <= 100.0, r.Name("exposure_rate"), " = ", a.exposure_rate_hz,
              ": at most 100 evaluations per second");
  r.Finish();
}

void ReadRunning(const toml::table& running, mechanics::ModelParams* p) {
  const TomlReader r(running, "running");
  mechanics::RunningParams g;
  g.segment = r.Positive("segment", g.segment);
  ThrowUnless(g.segment <= p->length, r.Name("segment"), " = ", g.segment,
              " m: longer than the intestine (", p->length, " m)");
  g.jaw_area = r.Positive("jaw_area", g.jaw_area);
  g.pinch_force = r.Positive("pinch_force", g.pinch_force);
  g.damage_dose = r.Positive("damage_dose", g.damage_dose);
  g.traction_break = r.Positive("traction_break", g.traction_break);
  g.camera_range = r.Positive("camera_range", g.camera_range);
  g.estimate_length = r.NonNegative("estimate_length", g.estimate_length);
  g.pass_coverage = r.Double("pass_coverage", g.pass_coverage);
  ThrowUnless(g.pass_coverage >= 0.0 && g.pass_coverage <= 1.0, r.Name("pass_coverage"), " = ",
              g.pass_coverage, ": must be in [0, 1]");
  g.pass_time = r.NonNegative("pass_time", g.pass_time);
  g.pass_path = r.NonNegative("pass_path", g.pass_path);
  g.pass_out_of_view = r.NonNegative("pass_out_of_view", g.pass_out_of_view);
  g.pass_reversals = r.NonNegative("pass_reversals", g.pass_reversals);
  g.pass_slips = r.NonNegative("pass_slips", g.pass_slips);
  g.pass_damage_events = r.NonNegative("pass_damage_events", g.pass_damage_events);
  g.pass_estimate_error = r.Positive("pass_estimate_error", g.pass_estimate_error);
  r.Finish();
  p->task.running = g;
}

}  // namespace viscera::scene
