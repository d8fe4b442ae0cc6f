#include "mechanics/grasps.h"

#include <algorithm>
#include <cmath>

namespace viscera::mechanics {
namespace {

constexpr double kGraspClose = 0.3;  // jaw opening below which the jaws grasp
constexpr double kGraspOpen = 0.6;   // ... and above which they release (hysteresis)
constexpr double kGraspDraw = 0.15;  // s: time constant drawing the tube into the jaws
constexpr double kGraspFade = 0.1;   // s: a released grasp fades out over this

// The curve parameter of the point of the centre line nearest to p, on the two segments
// between sphere k and its neighbours. The jaws hold the tube where they close on it: snapped to
// the nearest sphere's centre (12.5 mm apart on the cavity's tube), a tip half way between two
// spheres grasped one or the other by a hair, and the same gesture pulled the loop 1 cm apart at
// 100 Hz and 1 kHz (a 15 % different lift).
double NearestAlongChain(const collision::SphereChain& chain, int k, const Vec3& p) {
  const auto& spheres = chain.spheres();
  double best_s = spheres[k].s;
  double best_d2 = (spheres[k].centre - p).squaredNorm();
  for (int j : {k - 1, k + 1}) {
    if (j < 0 || j >= chain.size()) continue;
    const Vec3 d = spheres[j].centre - spheres[k].centre;
    const double len2 = d.squaredNorm();
    if (len2 <= 0.0) continue;
    const double u = std::clamp((p - spheres[k].centre).dot(d) / len2, 0.0, 1.0);
    const double d2 = (spheres[k].centre + u * d - p).squaredNorm();
    if (d2 < best_d2) best_d2 = d2, best_s = spheres[k].s + u * (spheres[j].s - spheres[k].s);
  }
  return best_s;
}

}  // namespace

Grasps::Grasps(const Model& model, const collision::SphereChain& chain, int held_span)
    : model_(model), chain_(chain), held_span_(held_span) {
  const size_t tools = model.params().tools.size();
  grasping_.assign(tools, false);
  grasp_at_.resize(tools);
  grasp_offset_.assign(tools, Vec3::Zero());
  grasp_scale_.assign(tools, 0.0);
  slipped_.assign(tools, 0);
  held_sphere_.assign(tools, -1);
}

bool Grasps::Follow(const State& state) {
  bool held_changed = false;
  for (size_t t = 0; t < state.tools.size() && t < grasping_.size(); ++t) {
    const ToolState& ts = state.tools[t];
    if (held_sphere_[t] != ts.held_sphere) held_changed = true;
    held_sphere_[t] = ts.held_sphere;
    grasping_[t] = ts.grasping;
    grasp_offset_[t] = ts.grasp_offset;
    grasp_scale_[t] = ts.grasp_scale;
    slipped_[t] = ts.slipped;
    if (ts.grasping) grasp_at_[t] = model_.MakeCurvePoint(ts.grasp_s);
  }
  return held_changed;
}

void Grasps::Update(int index, double h, bool active, const Points& q, ToolState* ts) {
  const ToolParams& tp = model_.params().tools[index];
  const bool closing = active && ts->jaw < kGraspClose;
  const bool opening = !active || ts->jaw > kGraspOpen;
  if (opening) slipped_[index] = 0;
  ts->grasp_pull = 0.0;
  // The grip grows as the jaws close past the grasping threshold (a grasper's ratchet).
  const double grip = tp.jaw_force * std::clamp((kGraspClose - ts->jaw) / kGraspClose, 0.0, 1.0);
  if (grasping_[index]) {
    grasp_offset_[index] *= std::exp(-h / kGraspDraw);
    ts->grasp_time += h;
    ts->grasp_jaw = std::min(ts->grasp_jaw, ts->jaw);
    // jaws opening let go: a release, not a slip
    const bool letting_go = ts->jaw > ts->grasp_jaw + 0.01;
    // Friction on two jaw faces holds at most 2 mu grip: a harder pull slides the tube out of
    // them, and it fades out like a release (a slip). Judged once the jaws have drawn the tube
    // in: while they close on it the grip is still growing from nothing.
    const double pull = Stiffness(index) * Stretch(index, ts->tip, q).norm();
    ts->grasp_pull = pull;
    if (tp.jaw_force > 0.0 && !slipped_[index] && !letting_go && ts->grasp_time > kGraspDraw &&
        pull > 2.0 * tp.jaw_friction * grip) {
      slipped_[index] = 1;
      ++ts->slips;
    }
    if (opening || slipped_[index]) grasp_scale_[index] -= h / kGraspFade;
    if (closing && !slipped_[index])
      grasp_scale_[index] = std::min(1.0, grasp_scale_[index] + h / kGraspFade);
    if (grasp_scale_[index] <= 0.0) grasping_[index] = false;
  } else if (closing && !slipped_[index]) {
    // Grasp the nearest part of the tube within reach of the jaws.
    const double reach =
        tp.grasp_reach > 0.0 ? tp.grasp_reach : 2.0 * (model_.params().radius + tp.radius);
    double best = reach;
    int nearest = -1;
    for (int k = 0; k < chain_.size(); ++k) {
      const double d = (chain_.spheres()[k].centre - ts->tip).norm();
      if (d < best) {
        best = d;
        nearest = k;
      }
    }
    if (nearest >= 0) {
      grasping_[index] = true;
      held_sphere_[index] = nearest;
      grasp_scale_[index] = 1.0;
      ts->grasp_time = 0.0;
      ts->grasp_jaw = ts->jaw;
      grasp_at_[index] = model_.MakeCurvePoint(NearestAlongChain(chain_, nearest, ts->tip));
      grasp_offset_[index] = ts->tip - Model::Evaluate(grasp_at_[index], q);
    }
  }
  // The state holds the grasp (Follow takes it back at the next step's start).
  ts->grasping = grasping_[index];
  ts->grasp_s = grasping_[index] ? grasp_at_[index].s : 0.0;
  ts->grasp_offset = grasp_offset_[index];
  ts->grasp_scale = grasp_scale_[index];
  ts->held_sphere = held_sphere_[index];
  ts->grip_force = grasping_[index] && !slipped_[index] ? grip : 0.0;
  ts->slipped = slipped_[index];
}

}  // namespace viscera::mechanics
