#include "scene/scene.h"

#include <fstream>
#include <sstream>
#include <toml++/toml.h>

#include "common/check.h"
#include "scene/shapes.h"
#include "scene/toml_reader.h"

namespace viscera::scene {
namespace {

using mechanics::AttachmentParams;
using mechanics::ContinuousScope;
using mechanics::IntegratorKind;
using mechanics::MassSolverKind;
using mechanics::ModelParams;

const toml::table& SubTable(const toml::table& root, const std::string& name) {
  const toml::node* node = root.get(name);
  ThrowUnless(node != nullptr, "[", name, "]: missing (required table)");
  ThrowUnless(node->is_table(), name, ": expected a table [", name, "]");
  return *node->as_table();
}

void ReadSimulation(const toml::table& table, ModelParams* p) {
  const TomlReader r(table, "simulation");
  p->rate_hz = r.Double("rate_hz", 100.0);
  ThrowUnless(p->rate_hz > 0.0, "simulation.rate_hz = ", p->rate_hz, ": must be > 0");
  p->substeps = r.Int("substeps", 1);
  ThrowUnless(p->substeps >= 1, "simulation.substeps = ", p->substeps, ": must be >= 1");
  const std::string integrator = r.String("integrator", "rk4");
  if (integrator == "rk4") {
    p->integrator = IntegratorKind::kRk4;
  } else if (integrator == "implicit") {
    p->integrator = IntegratorKind::kImplicitEuler;
  } else {
    Fail("simulation.integrator = \"", integrator, "\": expected \"rk4\" or \"implicit\"");
  }
  const std::string solver = r.String("mass_solver", "banded");
  if (solver == "banded") {
    p->mass_solver = MassSolverKind::kBanded;
  } else if (solver == "cholmod") {
    p->mass_solver = MassSolverKind::kCholmod;
  } else {
    Fail("simulation.mass_solver = \"", solver, "\": expected \"banded\" or \"cholmod\"");
  }
  const std::string linear = r.String("linear_solver", "banded");
  if (linear == "banded") {
    p->linear_solver = mechanics::LinearSolverKind::kBlockBand;
  } else if (linear == "cholmod") {
    p->linear_solver = mechanics::LinearSolverKind::kCholmod;
  } else {
    Fail("simulation.linear_solver = \"", linear, "\": expected \"banded\" or \"cholmod\"");
  }
  p->gravity = r.Vector("gravity", Vec3(0.0, 0.0, -9.81));
  r.Finish();
}

double NonNegative(const TomlReader& r, const std::string& key, double fallback) {
  const double v = r.Double(key, fallback);
  ThrowUnless(v >= 0.0, r.Name(key), " = ", v, ": must be >= 0");
  return v;
}

double Positive(const TomlReader& r, const std::string& key) {
  const double v = r.Double(key);
  ThrowUnless(v > 0.0, r.Name(key), " = ", v, ": must be > 0");
  return v;
}

std::vector<double> ReadPinned(const TomlReader& r) {
  std::vector<double> pins;
  const toml::node* node = r.Node("pinned");
  if (!node) return pins;
  const toml::array* a = node->as_array();
  ThrowUnless(a != nullptr, "intestine.pinned = ", Describe(*node), ": expected a list of \"start\", \"end\" or numbers in [0, 1]");
  for (const toml::node& item : *a) {
    if (item.is_string()) {
      const std::string s = item.as_string()->get();
      ThrowUnless(s == "start" || s == "end", "intestine.pinned: \"", s, "\": expected \"start\", \"end\" or a number in [0, 1]");
      pins.push_back(s == "start" ? 0.0 : 1.0);
    } else if (item.is_number()) {
      const double s = item.is_integer() ? static_cast<double>(item.as_integer()->get()) : item.as_floating_point()->get();
      ThrowUnless(s >= 0.0 && s <= 1.0, "intestine.pinned: ", s, ": curve parameters lie in [0, 1]");
      pins.push_back(s);
    } else {
      Fail("intestine.pinned: ", Describe(item), ": expected \"start\", \"end\" or a number in [0, 1]");
    }
  }
  return pins;
}

void ReadIntestine(const toml::table& table, ModelParams* p) {
  const TomlReader r(table, "intestine");
  p->length = Positive(r, "length");
  p->radius = Positive(r, "radius");
  p->mass = Positive(r, "mass");
  const int n = r.Int("control_points", 0);
  p->stretch_stiffness = NonNegative(r, "stretch_stiffness", 0.0);
  p->bend_stiffness = NonNegative(r, "bend_stiffness", 0.0);
  p->bend_reference_curvature = NonNegative(r, "bend_reference_curvature", 0.0);
  p->continuous_stretch = NonNegative(r, "continuous_stretch", 0.0);
  const std::string scope = r.String("continuous_scope", "global");
  ThrowUnless(scope == "global" || scope == "segment", "intestine.continuous_scope = \"", scope,
              "\": expected \"global\" or \"segment\"");
  p->continuous_scope = scope == "global" ? ContinuousScope::kGlobal : ContinuousScope::kSegment;
  p->damping = NonNegative(r, "damping", 0.0);
  p->spring_damping = NonNegative(r, "spring_damping", 0.0);
  p->pinned = ReadPinned(r);
  const toml::node* shape = r.Node("shape");
  ThrowUnless(shape != nullptr, "[intestine.shape]: missing (required table)");
  ThrowUnless(shape->is_table(), "intestine.shape: expected a table");
  p->initial_q = MakeShape(TomlReader(*shape->as_table(), "intestine.shape"), n, p->length);
  r.Finish();
}

std::vector<const toml::table*> TableArray(const toml::table& root, const std::string& name) {
  std::vector<const toml::table*> out;
  const toml::node* node = root.get(name);
  if (!node) return out;
  const toml::array* a = node->as_array();
  ThrowUnless(a != nullptr && a->is_array_of_tables(), name, ": expected [[", name, "]] tables");
  for (const toml::node& t : *a) out.push_back(t.as_table());
  return out;
}

void ReadAttachments(const toml::table& root, ModelParams* p) {
  int index = 0;
  for (const toml::table* t : TableArray(root, "attachment")) {
    const TomlReader r(*t, "attachment[" + std::to_string(index++) + "]");
    AttachmentParams a;
    a.s = r.Double("at");
    ThrowUnless(a.s >= 0.0 && a.s <= 1.0, r.Name("at"), " = ", a.s, ": curve parameters lie in [0, 1]");
    if (r.Has("point")) a.point = r.Vector("point");
    a.stiffness = Positive(r, "stiffness");
    a.damping = NonNegative(r, "damping", 0.0);
    a.rest_length = NonNegative(r, "rest_length", 0.0);
    r.Finish();
    p->attachments.push_back(a);
  }
}

void ReadObstacles(const toml::table& root, Scene* scene) {
  int index = 0;
  for (const toml::table* t : TableArray(root, "obstacle")) {
    const TomlReader r(*t, "obstacle[" + std::to_string(index++) + "]");
    Obstacle o;
    o.kind = r.String("kind");
    ThrowUnless(o.kind == "plane", r.Name("kind"), " = \"", o.kind, "\": only \"plane\" is known to this version");
    o.point = r.Vector("point");
    o.normal = r.Vector("normal");
    ThrowUnless(o.normal.norm() > 1e-12, r.Name("normal"), ": must not be zero");
    o.normal.normalize();
    r.Finish();
    scene->obstacles.push_back(o);
  }
  if (!scene->obstacles.empty()) {
    scene->warnings.push_back(Cat(scene->obstacles.size(),
                                  " obstacle(s) parsed but not simulated: contacts are not part of this "
                                  "build yet, so the intestine passes through them"));
  }
}

Scene Build(const toml::table& root, const std::string& source) {
  Scene scene;
  scene.source = source;
  for (const auto& [key, node] : root) {
    const std::string k(key.str());
    if (k == "simulation" || k == "intestine" || k == "attachment" || k == "obstacle") continue;
    scene.warnings.push_back(Cat("unknown top-level table [", k, "] ignored"));
  }
  if (root.contains("simulation")) ReadSimulation(SubTable(root, "simulation"), &scene.model);
  ReadIntestine(SubTable(root, "intestine"), &scene.model);
  ReadAttachments(root, &scene.model);
  ReadObstacles(root, &scene);
  return scene;
}

}  // namespace

Scene ParseScene(const std::string& text, const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    Fail(source, ":", where.line, ":", where.column, ": ", e.description());
  }
  try {
    return Build(root, source);
  } catch (const InputError& e) {
    Fail(source, ": ", e.what());
  }
}

Scene LoadSceneFile(const std::string& path) {
  std::ifstream in(path);
  ThrowUnless(in.good(), path, ": cannot open scene file");
  std::stringstream text;
  text << in.rdbuf();
  return ParseScene(text.str(), path);
}

}  // namespace viscera::scene
