#include "scene/scene.h"

#include <toml++/toml.h>
#include <fstream>
#include <sstream>

#include "common/check.h"
#include "mechanics/implicit_euler.h"
#include "mechanics/step.h"
#include "scene/camera_table.h"
#include "scene/mesentery_table.h"
#include "scene/shapes.h"
#include "scene/task_reader.h"
#include "scene/toml_bounds.h"
#include "scene/toml_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>

namespace viscera::scene {
namespace {

using mechanics::AttachmentParams;
using mechanics::ContinuousScope;
using mechanics::IntegratorKind;
using mechanics::MassSolverKind;
using mechanics::ModelParams;
using mechanics::TissueCard;

const toml::table& SubTable(const toml::table& root, const std::string& name) {
  const toml::node* node = root.get(name);
  ThrowUnless(node != nullptr, "[", name, "]: missing (required table)");
  ThrowUnless(node->is_table(), name, ": expected a table [", name, "]");
  return *node->as_table();
}

// Refuses `value` above `limit` (when the limit is set) with the key and the limit.
template <typename T>
void WithinLimit(const std::string& what, T value, T limit) {
  ThrowUnless(limit <= 0 || value <= limit, what, " = ", value, ": above this server's limit of ",
              limit);
}

void ReadSimulation(const toml::table& table, const SceneLimits& limits, ModelParams* p,
                    double* settle) {
  const TomlReader r(table, "simulation");
  *settle = r.Double("settle", 0.0);
  ThrowUnless(*settle >= 0.0 && *settle <= 60.0, "simulation.settle = ", *settle,
              ": expected 0..60 s");
  WithinLimit("simulation.settle", *settle, limits.max_settle_s);
  p->rate_hz = r.Double("rate_hz", 100.0);
  ThrowUnless(p->rate_hz > 0.0, "simulation.rate_hz = ", p->rate_hz, ": must be > 0");
  WithinLimit("simulation.rate_hz", p->rate_hz, limits.max_rate_hz);
  p->substeps = r.Int("substeps", 1);
  ThrowUnless(p->substeps >= 1, "simulation.substeps = ", p->substeps, ": must be >= 1");
  WithinLimit("simulation.substeps", p->substeps, limits.max_substeps);
  p->integrator = r.Choice<IntegratorKind>(
      "integrator", {{"rk4", IntegratorKind::kRk4}, {"implicit", IntegratorKind::kImplicitEuler}});
  p->mass_solver = r.Choice<MassSolverKind>(
      "mass_solver", {{"banded", MassSolverKind::kBanded}, {"cholmod", MassSolverKind::kCholmod}});
  p->linear_solver = r.Choice<mechanics::LinearSolverKind>(
      "linear_solver", {{"banded", mechanics::LinearSolverKind::kBlockBand},
                        {"cholmod", mechanics::LinearSolverKind::kCholmod}});
  p->gravity = r.Vector("gravity", Vec3(0.0, 0.0, -9.81));
  p->linearization_guard = r.Bool("linearization_guard", p->linearization_guard);
  p->implicit_scheme = r.Choice<mechanics::ImplicitScheme>(
      "implicit_scheme", {{"bdf2", mechanics::ImplicitScheme::kBdf2},
                          {"backward_euler", mechanics::ImplicitScheme::kBackwardEuler}});
  // only ever lowered: a session may make its own solves cruder, never dearer
  constexpr int kCap = mechanics::ImplicitEulerIntegrator::kMaxCgIterationsExtended;
  if (r.Has("cg_iteration_cap")) {
    p->cg_iteration_cap = r.Int("cg_iteration_cap");
    ThrowUnless(p->cg_iteration_cap >= 1 && p->cg_iteration_cap <= kCap,
                "simulation.cg_iteration_cap = ", p->cg_iteration_cap, ": expected 1..", kCap);
  }
  r.Finish();
}

// A parameter within [lo, hi]: for a tool, what a haptic device and the coupling can render (a
// stiffness of 1e308 or a mass of 1e-300 made every force sent non-finite).
double Within(const TomlReader& r, const std::string& key, double fallback, double lo, double hi,
              const char* unit) {
  const double v = r.Double(key, fallback);
  ThrowUnless(v >= lo && v <= hi, r.Name(key), " = ", v, ": expected ", lo, "..", hi, " ", unit);
  return v;
}

std::vector<double> ReadPinned(const TomlReader& r) {
  std::vector<double> pins;
  const toml::node* node = r.Node("pinned");
  if (!node) return pins;
  const toml::array* a = node->as_array();
  ThrowUnless(a != nullptr, "intestine.pinned = ", Describe(*node),
              ": expected a list of \"start\", \"end\" or numbers in [0, 1]");
  for (const toml::node& item : *a) {
    if (item.is_string()) {
      const std::string s = item.as_string()->get();
      ThrowUnless(s == "start" || s == "end", "intestine.pinned: \"", s,
                  "\": expected \"start\", \"end\" or a number in [0, 1]");
      pins.push_back(s == "start" ? 0.0 : 1.0);
    } else if (item.is_number()) {
      const double s = item.is_integer() ? static_cast<double>(item.as_integer()->get())
                                         : item.as_floating_point()->get();
      ThrowUnless(s >= 0.0 && s <= 1.0, "intestine.pinned: ", s,
                  ": curve parameters lie in [0, 1]");
      pins.push_back(s);
    } else {
      Fail("intestine.pinned: ", Describe(item),
           ": expected \"start\", \"end\" or a number in [0, 1]");
    }
  }
  return pins;
}

void ReadIntestine(const toml::table& table, const SceneLimits& limits, ModelParams* p) {
  const TomlReader r(table, "intestine");
  p->length = r.Positive("length");
  p->radius = r.Positive("radius", TissueCard::kRadius);
  p->mass = r.Positive("mass", TissueCard::kLinearDensity * p->length);
  // the collision chain's size, known before anything is built (a tiny radius asked for
  // gigabytes of spheres and their pairs)
  const double spheres = std::ceil(p->length / p->radius) + 1.0;
  ThrowUnless(limits.max_spheres <= 0 || spheres <= limits.max_spheres,
              "intestine.length / intestine.radius = ", spheres,
              " collision spheres: above this server's limit of ", limits.max_spheres,
              " (a shorter or wider tube)");
  const int n = r.Int("control_points", 0);
  WithinLimit("intestine.control_points", n, limits.max_control_points);
  p->stretch_stiffness = r.NonNegative("stretch_stiffness", TissueCard::kStretchStiffness);
  p->bend_stiffness = r.NonNegative("bend_stiffness", TissueCard::kBendStiffness);
  p->bend_reference_curvature = r.NonNegative("bend_reference_curvature", 0.0);
  p->continuous_stretch = r.NonNegative("continuous_stretch", 0.0);
  p->continuous_scope = r.Choice<ContinuousScope>(
      "continuous_scope",
      {{"global", ContinuousScope::kGlobal}, {"segment", ContinuousScope::kSegment}});
  p->damping = r.NonNegative("damping", 0.0);
  p->spring_damping = r.NonNegative("spring_damping", 0.0);
  p->pinned = ReadPinned(r);
  const toml::node* shape = r.Node("shape");
  ThrowUnless(shape != nullptr, "[intestine.shape]: missing (required table)");
  ThrowUnless(shape->is_table(), "intestine.shape: expected a table");
  p->initial_q = MakeShape(TomlReader(*shape->as_table(), "intestine.shape"), n, p->length);
  WithinLimit("intestine.shape points", static_cast<int>(p->initial_q.rows()),
              limits.max_control_points);
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
    ThrowUnless(a.s >= 0.0 && a.s <= 1.0, r.Name("at"), " = ", a.s,
                ": curve parameters lie in [0, 1]");
    if (r.Has("point")) a.point = r.Vector("point");
    a.stiffness = r.Positive("stiffness");
    a.damping = r.NonNegative("damping", 0.0);
    a.rest_length = r.NonNegative("rest_length", 0.0);
    r.Finish();
    p->attachments.push_back(a);
  }
}

// The triangles of an OBJ file's faces (a polygon of n vertices is n - 2), counted up to one
// past `stop` before anything is built: a 2M-triangle mesh within the byte limit took 150 s.
int CountObjTriangles(const std::string& path, int stop) {
  std::ifstream in(path);
  ThrowUnless(in.good(), path, ": cannot open mesh");
  int triangles = 0;
  for (std::string line; triangles <= stop && std::getline(in, line);) {
    if (line.size() < 2 || line[0] != 'f' || (line[1] != ' ' && line[1] != '\t')) continue;
    std::istringstream tokens(line.substr(1));
    int vertices = 0;
    for (std::string token; tokens >> token;) ++vertices;
    triangles += std::max(0, vertices - 2);
  }
  return triangles;
}

collision::Obstacle ReadObstacle(const TomlReader& r, const std::string& base_dir,
                                 const SceneLimits& limits) {
  using collision::ObstacleKind;
  collision::Obstacle o;
  const std::string kind = r.String("kind");
  o.name = r.String("name", kind);
  o.inside = r.Bool("inside", false);
  auto orientation = [&]() -> Eigen::Quaterniond {
    const toml::node* node = r.Node("orientation");
    if (!node) return Eigen::Quaterniond::Identity();
    const toml::array* a = node->as_array();
    ThrowUnless(a && a->size() == 4, r.Name("orientation"), " = ", Describe(*node),
                ": expected [w, x, y, z]");
    double v[4];
    for (int i = 0; i < 4; ++i) {
      const toml::node& e = *a->get(i);
      ThrowUnless(e.is_number(), r.Name("orientation"), ": expected numbers");
      v[i] = e.is_integer() ? static_cast<double>(e.as_integer()->get())
                            : e.as_floating_point()->get();
    }
    const Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
    ThrowUnless(std::isfinite(q.norm()) && q.norm() > 1e-9, r.Name("orientation"),
                ": must be a non-zero quaternion");
    return q.normalized();
  };
  if (kind == "plane") {
    o.kind = ObstacleKind::kPlane;
    o.point = r.Vector("point");
    o.normal = r.Vector("normal");
    ThrowUnless(o.normal.norm() > 1e-12, r.Name("normal"), ": must not be zero");
    o.normal.normalize();
  } else if (kind == "sphere") {
    o.kind = ObstacleKind::kSphere;
    o.centre = r.Vector("centre");
    o.radius = r.Positive("radius");
  } else if (kind == "capsule") {
    o.kind = ObstacleKind::kCapsule;
    o.a = r.Vector("a");
    o.b = r.Vector("b");
    o.radius = r.Positive("radius");
  } else if (kind == "box") {
    o.kind = ObstacleKind::kBox;
    o.centre = r.Vector("centre");
    o.half_extents = r.Vector("half_extents");
    ThrowUnless(o.half_extents.minCoeff() > 0.0, r.Name("half_extents"), ": must be > 0");
    o.orientation = orientation();
  } else if (kind == "ellipsoid") {
    o.kind = ObstacleKind::kEllipsoid;
    o.centre = r.Vector("centre");
    o.radii = r.Vector("radii");
    ThrowUnless(o.radii.minCoeff() > 0.0, r.Name("radii"), ": must be > 0");
    o.orientation = orientation();
  } else if (kind == "mesh") {
    o.kind = ObstacleKind::kMesh;
    std::string file = r.String("file");
    if (limits.resolve_file) {
      file = limits.resolve_file(file);
    } else if (!file.empty() && file[0] != '/') {
      file = base_dir + file;
    }
    const double scale = r.Double("scale", 1.0);
    ThrowUnless(scale > 0.0, r.Name("scale"), " = ", scale, ": must be > 0");
    const int resolution = r.Int("resolution", 40);
    ThrowUnless(resolution >= 8 && resolution <= 200, r.Name("resolution"), " = ", resolution,
                ": expected 8..200");
    WithinLimit(r.Name("resolution"), resolution, limits.max_mesh_resolution);
    if (limits.max_mesh_triangles > 0) {
      WithinLimit(r.Name("file") + " triangles", CountObjTriangles(file, limits.max_mesh_triangles),
                  limits.max_mesh_triangles);
    }
    o.sdf = std::make_shared<collision::MeshSdf>(
        collision::MeshSdf::FromObj(file, scale, r.Vector("offset", Vec3::Zero()), resolution));
  } else {
    Fail(r.Name("kind"), " = \"", kind,
         "\": expected plane, sphere, capsule, box, ellipsoid or mesh");
  }
  r.Finish();
  return o;
}

void ReadObstacles(const toml::table& root, const std::string& base_dir, const SceneLimits& limits,
                   ModelParams* p) {
  int index = 0;
  const std::vector<const toml::table*> tables = TableArray(root, "obstacle");
  WithinLimit("[[obstacle]] count", static_cast<int>(tables.size()), limits.max_obstacles);
  for (const toml::table* t : tables) {
    if (limits.check_stop) limits.check_stop();
    p->obstacles.push_back(ReadObstacle(TomlReader(*t, "obstacle[" + std::to_string(index++) + "]"),
                                        base_dir, limits));
  }
}

void ReadContacts(const toml::table& root, const SceneLimits& limits, ModelParams* p) {
  mechanics::ContactParams& c = p->contacts;
  c.self = true;  // a scene never lets the tube pass through itself unless it says so
  const toml::node* node = root.get("contacts");
  if (!node) return;
  ThrowUnless(node->is_table(), "contacts: expected a table [contacts]");
  const TomlReader r(*node->as_table(), "contacts");
  c.self = r.Bool("self", true);
  // Bounded by what the contacts can hold: at 1e6 N/m every closing pair is an impact, and the
  // impulses' dense system over thousands of them took 7 GB and minutes per step.
  c.stiffness = Within(r, "stiffness", c.stiffness, 1.0, 1e5, "N/m");
  c.damping = Within(r, "damping", c.damping, 0.0, 1e3, "N s/m");
  c.friction = r.NonNegative("friction", c.friction);
  c.self_friction = r.NonNegative("self_friction", c.self_friction);
  c.tool_friction = r.NonNegative("tool_friction", c.tool_friction);
  c.friction_law =
      r.Choice<mechanics::FrictionLaw>("friction_law",
                                       {{"stick_slip", mechanics::FrictionLaw::kStickSlip},
                                        {"regularized", mechanics::FrictionLaw::kRegularized}},
                                       c.friction_law);
  c.tangential_stiffness =
      Within(r, "tangential_stiffness", c.tangential_stiffness, 0.0, 1e5, "N/m");
  c.margin = r.NonNegative("margin", 0.25 * p->radius);
  ThrowUnless(limits.max_margin_radii <= 0.0 || c.margin <= limits.max_margin_radii * p->radius,
              "contacts.margin = ", c.margin, " m: above this server's limit of ",
              limits.max_margin_radii, " tube radii (", limits.max_margin_radii * p->radius, " m)");
  c.exact_pairs = r.Choice<bool>("coupling", {{"exact", true}, {"band", false}});
  c.impact_depth = r.NonNegative("impact_depth", c.impact_depth);
  c.impact_constraints = r.Bool("impact_constraints", c.impact_constraints);
  c.spheres_follow_material = r.Choice<bool>("spheres", {{"material", true}, {"arc_length", false}},
                                             c.spheres_follow_material);
  r.Finish();
}

void ReadTools(const toml::table& root, const SceneLimits& limits, ModelParams* p) {
  int index = 0;
  const std::vector<const toml::table*> tables = TableArray(root, "tool");
  WithinLimit("[[tool]] count", static_cast<int>(tables.size()), limits.max_tools);
  for (const toml::table* t : tables) {
    const TomlReader r(*t, "tool[" + std::to_string(index++) + "]");
    mechanics::ToolParams tool;
    tool.name = r.String("name");
    ThrowUnless(!tool.name.empty() && tool.name.size() <= 32 &&
                    std::all_of(tool.name.begin(), tool.name.end(),
                                [](char ch) {
                                  return std::isalnum(static_cast<unsigned char>(ch)) ||
                                         ch == '_' || ch == '-';
                                }),
                r.Name("name"), " = \"", tool.name, "\": use 1 to 32 letters, digits, '_' or '-'");
    for (const mechanics::ToolParams& other : p->tools) {
      ThrowUnless(other.name != tool.name, r.Name("name"), " = \"", tool.name,
                  "\": two tools share this name");
    }
    tool.port = r.Vector("port");
    tool.radius = Within(r, "radius", tool.radius, 1e-4, 0.05, "m");
    tool.length = Within(r, "length", tool.length, 0.01, 2.0, "m");
    tool.max_force = Within(r, "max_force", tool.max_force, 1e-3, 100.0, "N");
    tool.coupling_stiffness =
        Within(r, "coupling_stiffness", tool.coupling_stiffness, 1e-3, 1e5, "N/m");
    tool.coupling_damping = Within(r, "coupling_damping", tool.coupling_damping, 0.0, 1e3, "N s/m");
    tool.mass = Within(r, "mass", tool.mass, 1e-3, 10.0, "kg");
    tool.grasp_stiffness = Within(r, "grasp_stiffness", tool.grasp_stiffness, 1e-3, 1e5, "N/m");
    tool.grasp_reach = Within(r, "grasp_reach", tool.grasp_reach, 0.0, 0.1, "m");
    tool.jaw_force = Within(r, "jaw_force", tool.jaw_force, 0.0, 100.0, "N");
    tool.jaw_friction = Within(r, "jaw_friction", tool.jaw_friction, 1e-3, 2.0, "");
    tool.idle_timeout = Within(r, "idle_timeout", tool.idle_timeout, 1e-3, 60.0, "s");
    r.Finish();
    p->tools.push_back(tool);
  }
}

constexpr int kTighten = 10;

// How far the starting pose overstretches the mesentery's longest-pulled tether (m, 0 if none).
double TetherExcess(const mechanics::Model& model, const Points& q) {
  double excess = 0.0;
  for (const mechanics::Tether& t : model.tethers())
    excess = std::max(excess, (mechanics::Model::Evaluate(t.at, q) - t.root).norm() - t.length);
  return excess;
}

// `p` as the settle steps it in `stage` (of kTighten + 1 when the start overstretches the
// mesentery by `excess`): the tethers' slack lengthened by what is left of the excess, and
// friction without a static phase. The settle stands for the minutes in which breathing and
// peristalsis lay the bowel where it rests: without a static phase it creeps into the low places;
// the session then starts from that rest under Coulomb's law (docs/friction.md).
ModelParams SettleStage(ModelParams p, double excess, int stage) {
  p.contacts.friction_law = mechanics::FrictionLaw::kRegularized;
  if (p.mesentery)
    p.mesentery->extra_slack = excess * (1.0 - static_cast<double>(stage) / kTighten);
  return p;
}

// The model of the settle's first steps, which SceneLimits::vet times before the settle is paid
// for: as the settle runs them (at the scene's own rate), not as a session would.
ModelParams SettleStart(const ModelParams& p) {
  return SettleStage(p, TetherExcess(mechanics::Model(p), p.initial_q), 0);
}

// Lets the intestine fall and settle for `seconds` (no tools) and makes the result the start.
// Anchors that default to the starting pose are fixed first, so they stay where the scene put them.
// A mesentery whose tethers the starting pose overstretches is tightened gradually over the first
// two thirds of the time (its slack starts long enough for every tether, and shrinks to the
// scene's in kTighten stages): pulled taut at once, the far tethers would drag the tube through
// itself.
void Settle(double seconds, const std::function<void()>& check_stop, ModelParams* p) {
  const mechanics::Model before(*p);
  for (size_t i = 0; i < p->attachments.size(); ++i)
    p->attachments[i].point = before.attachments()[i].anchor;
  const double excess = TetherExcess(before, p->initial_q);
  const int stages = excess > 0.0 ? kTighten + 1 : 1;
  const int total_steps = static_cast<int>(std::lround(seconds * p->rate_hz));
  mechanics::State state = mechanics::InitialState(before);
  for (int stage = 0; stage < stages; ++stage) {
    const mechanics::Model model(SettleStage(*p, excess, stage));
    mechanics::Workspace workspace(model);
    mechanics::ForgetSolverMemory(&state);  // each stage's model starts its solver anew
    // stage k < kTighten gets 1 / (1.5 kTighten) of the time, the last one the remaining third
    const int begin = stage * total_steps * 2 / (3 * kTighten);
    const int end =
        stage + 1 < stages ? (stage + 1) * total_steps * 2 / (3 * kTighten) : total_steps;
    for (int k = begin; k < end; ++k) {
      if (check_stop) check_stop();  // an atomic load and a clock read: nothing beside a step
      mechanics::Step(model, {}, &state, &workspace);
    }
  }
  ThrowUnless(state.nonfinite_resets == 0, "simulation.settle: the scene blew up while settling");
  p->initial_q = state.q;
}

Scene Build(const toml::table& root, const std::string& source, const SceneLimits& limits) {
  Scene scene;
  scene.source = source;
  for (const auto& [key, node] : root) {
    const std::string k(key.str());
    if (k == "simulation" || k == "intestine" || k == "attachment" || k == "obstacle" ||
        k == "contacts" || k == "tool" || k == "mesentery" || k == "target" || k == "assessment" ||
        k == "running" || k == "camera") {
      continue;
    }
    scene.warnings.push_back(Cat("unknown top-level table [", k, "] ignored"));
  }
  double settle = 0.0;
  if (root.contains("simulation"))
    ReadSimulation(SubTable(root, "simulation"), limits, &scene.model, &settle);
  ReadIntestine(SubTable(root, "intestine"), limits, &scene.model);
  ReadAttachments(root, &scene.model);
  scene.model.mesentery = ReadMesentery(root);
  const size_t slash = source.find_last_of('/');
  ReadObstacles(root, slash == std::string::npos ? std::string() : source.substr(0, slash + 1),
                limits, &scene.model);
  if (limits.check_stop) limits.check_stop();  // after the distance fields
  CheckStartClear(scene.model.initial_q, scene.model.radius, scene.model.obstacles);
  ReadContacts(root, limits, &scene.model);
  ReadTools(root, limits, &scene.model);
  ReadTask(TableArray(root, "target"),
           root.contains("assessment") ? &SubTable(root, "assessment") : nullptr, &scene.model);
  if (root.contains("running")) ReadRunning(SubTable(root, "running"), &scene.model);
  scene.model.scope = ReadCamera(root);
  if (settle > 0.0) {
    // The settle runs without the linearization guard and with backward Euler alone, and is
    // vetted so: it is how the scene reaches its start, not time anyone feels, and the shipped
    // piles (on which the training task's gesture was designed, docs/training.md) are the plain
    // step's.
    const bool guard = scene.model.linearization_guard;
    const mechanics::ImplicitScheme scheme = scene.model.implicit_scheme;
    scene.model.linearization_guard = false;
    if (limits.check_stop) limits.check_stop();
    scene.model.implicit_scheme = mechanics::ImplicitScheme::kBackwardEuler;
    if (limits.vet) limits.vet(SettleStart(scene.model), false);
    Settle(settle, limits.check_stop, &scene.model);
    scene.model.linearization_guard = guard;
    scene.model.implicit_scheme = scheme;
  }
  if (limits.check_stop) limits.check_stop();
  if (limits.vet) limits.vet(scene.model, true);
  return scene;
}

}  // namespace

Scene ParseScene(const std::string& text, const std::string& source) {
  return ParseScene(text, source, SceneLimits{});
}

Scene ParseScene(const std::string& text, const std::string& source, const SceneLimits& limits) {
  try {
    CheckTomlBounds(text);  // before the parser, which recurses once per level of a key
  } catch (const InputError& e) {
    Fail(source, ": ", e.what());
  }
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    Fail(source, ":", where.line, ":", where.column, ": ", e.description());
  }
  try {
    return Build(root, source, limits);
  } catch (const InputError& e) {
    Fail(source, ": ", e.what());
  }
}

Scene LoadSceneFile(const std::string& path) {
  std::ifstream in(path);
  ThrowUnless(in.good(), path, ": cannot open scene file");
  // at most one byte past the limit: a huge file (or /dev/zero) is refused, not read whole
  std::string text(kSceneTomlBounds.max_bytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(in.gcount()));
  return ParseScene(text, path);
}

void ChangeRate(mechanics::ModelParams* params, double rate_hz) {
  const double substep = 1.0 / (params->rate_hz * params->substeps);
  // The small slack keeps exact multiples (100 Hz x 2 -> 200 Hz x 1) from rounding up.
  params->substeps = std::max(1, static_cast<int>(std::ceil(1.0 / (rate_hz * substep) - 1e-9)));
  params->rate_hz = rate_hz;
}

}  // namespace viscera::scene
