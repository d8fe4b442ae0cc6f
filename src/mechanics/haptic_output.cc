#include "mechanics/haptic_output.h"

#include <algorithm>

namespace viscera::mechanics {
namespace {

// Series stiffness of the coupling and a contact: what the hand feels through the tool.
double Series(double a, double b) { return a > 0.0 && b > 0.0 ? a * b / (a + b) : 0.0; }

}  // namespace

HapticOutput::HapticOutput(const Model& model, bool tips_in_solve)
    : model_(model), tips_in_solve_(tips_in_solve) {
  const size_t tools = model.params().tools.size();
  impulse_.assign(tools, Vec3::Zero());
  time_.assign(tools, 0.0);
  saturated_.assign(tools, 0);
}

void HapticOutput::StartStep() {
  std::fill(impulse_.begin(), impulse_.end(), Vec3::Zero());
  std::fill(time_.begin(), time_.end(), 0.0);
  std::fill(saturated_.begin(), saturated_.end(), 0);
}

void HapticOutput::EndStep(const std::vector<collision::ContactCandidate>& list,
                           const std::vector<PairGeometry>& geometry, const ContactLaw& law,
                           const Grasps& grasps, State* state) const {
  // The coupling's reaction, k (tip - target) + c v, faded when idle.
  for (size_t t = 0; t < state->tools.size(); ++t) {
    const ToolParams& tp = model_.params().tools[t];
    ToolState& ts = state->tools[t];
    if (!ts.initialized) continue;
    const double kc = ts.coupling_scale * tp.coupling_stiffness;
    Vec3 f = ts.target.tip.allFinite() ? Vec3(kc * (ts.tip - ts.target.tip)) : Vec3::Zero();
    f += ts.coupling_scale * tp.coupling_damping * ts.tip_velocity;
    bool saturated = false;
    if (tips_in_solve_ && time_[t] > 0.0) {
      // The step's impulse on the hand over its length: what the solve's coupling applied.
      f = impulse_[t] / time_[t];
      saturated = saturated_[t];
    }
    ts.clamped = saturated || f.norm() > tp.max_force;
    if (ts.clamped) f *= tp.max_force / f.norm();
    ts.force = f;
    ts.torque = (ts.tip - tp.port).cross(f);
    // Local stiffness: each touching contact (and the grasp) in series with the coupling.
    Mat3 k = Mat3::Zero();
    for (size_t i = 0; i < list.size(); ++i) {
      const collision::ContactCandidate& c = list[i];
      if (c.kind != collision::ContactKind::kTool || c.b != static_cast<int>(t)) continue;
      const PairGeometry& p = geometry[i];
      // The contact's stiffness along n, moved to the tip: L n n' L = m m'.
      const Vec3 m = p.lever.Apply(p.normal);
      const double m2 = m.squaredNorm();
      if (p.depth > 0.0 && m2 > 0.0)
        k += Series(kc, m2 * law.At(p.depth).slope) * (m * m.transpose()) / m2;
    }
    if (grasps.grasping(static_cast<int>(t)))
      k += Series(kc, grasps.Stiffness(static_cast<int>(t))) * Mat3::Identity();
    ts.stiffness = k;
  }
}

}  // namespace viscera::mechanics
