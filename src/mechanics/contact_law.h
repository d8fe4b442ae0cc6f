#pragma once
/// The contacts' force law (France et al. 2005 section 3.5): a penalty spring along the normal,
/// linear up to contacts.impact_depth and stiffening beyond it, with damping, and the regularized
/// Coulomb friction (or, for stick-slip friction, the cone's normal force that StickSlipFriction
/// reads). It knows nothing of the chain, the candidates or the tools: given a contact's geometry
/// and relative velocity it says the force, so the integrator's force evaluations, the tools' own
/// cycles and the haptic stiffness all apply the same law. Inline: it runs for every candidate
/// of every force evaluation.
#include <algorithm>

#include "collision/contact_detector.h"
#include "common/types.h"
#include "mechanics/model_params.h"

namespace viscera::mechanics {

/// The lever rule of a tool contact (docs/tool-coupling.md). The shaft pivots at the port and
/// slides through it, so its point at `fraction` of the way from the port to the tip moves at
/// L v_tip, L = fraction I + (1 - fraction) a a' with a along the shaft, and a force f there acts
/// on the tip as L f: the port takes the rest, across the shaft only (a trocar holds no force
/// along the shaft). L is the identity at the tip and for contacts that are not a tool's.
struct ShaftLever {
  double fraction = 1.0;     // from the port (0) to the tip (1)
  Vec3 axis = Vec3::Zero();  // unit, from the port to the tip
  /// L v: a tip velocity's at the contact, or a force at the contact's on the tip (L = L').
  Vec3 Apply(const Vec3& v) const { return fraction * v + ((1.0 - fraction) * axis.dot(v)) * axis; }
  Mat3 Matrix() const {
    return fraction * Mat3::Identity() + (1.0 - fraction) * axis * axis.transpose();
  }
};

/// One contact candidate's geometry (ContactGeometry), kept for every candidate of the list: the
/// law's output is not part of it, so that the narrow phase writes and its readers scan little.
struct PairGeometry {
  Vec3 normal = Vec3::Zero();
  double depth = 0.0;      // penetration (m), > 0 when active
  double clearance = 0.0;  // signed distance beyond contact (m)
  ShaftLever lever;        // tool contacts: where on the shaft
};

/// One contact candidate at one evaluation: its geometry and, once the law has been evaluated on
/// it, its force.
struct ContactPenalty : PairGeometry {
  bool active = false;
  Vec3 force = Vec3::Zero();  // on the sphere
  double normal_force = 0.0;  // N, stick-slip: the friction cone's normal force when active
  Vec3 slip = Vec3::Zero();   // tangential relative velocity (m/s) when active
};

class ContactLaw {
 public:
  /// @pre cp outlives this.
  ContactLaw(const ContactParams& cp, double radius) : cp_(cp), radius_(radius) {}

  /// The stiffening law's goal (fraction of R): the slope reaches kStiffening k at this depth,
  /// and the held constraints bound depths short of it (impact_sets.cc).
  static constexpr double kDepthGoal = 0.10;
  /// The slope's growth from k at impact_depth to kDepthGoal.
  static constexpr double kStiffening = 100.0;

  /// The penalty law at a penetration depth: force (N), slope (N/m), stored energy (J).
  struct Law {
    double force, slope, energy;
  };
  /// At `depth` (m); linear (k) at any depth up to impact_depth, apart (depth < 0) included: a
  /// speculative pair's force k depth and slope k. Beyond impact_depth d1, f = k d + s (d - d1)^2
  /// with s such that the slope reaches kStiffening k at kDepthGoal; its energy
  /// k d^2 / 2 + s (d - d1)^3 / 3 is the force's integral, so it stores what it takes and returns
  /// it.
  Law At(double depth) const {
    Law law{cp_.stiffness * depth, cp_.stiffness, 0.5 * cp_.stiffness * depth * depth};
    const double d1 = cp_.impact_depth * radius_;
    // Tools' contacts too: linear, a tool pressing a loop into the wall sank by its force over k
    // (80 % of R at 5 N; docs/tool-coupling.md).
    if (!(cp_.impact_depth > 0.0) || cp_.impact_depth >= kDepthGoal || depth <= d1) return law;
    const double s =
        (kStiffening - 1.0) * cp_.stiffness / (2.0 * (kDepthGoal - cp_.impact_depth) * radius_);
    const double e = depth - d1;
    law.force += s * e * e;
    law.slope += 2.0 * s * e;
    law.energy += s * e * e * e / 3.0;
    return law;
  }

  /// The Coulomb coefficient of a kind of pair.
  double Friction(collision::ContactKind kind) const {
    switch (kind) {
      case collision::ContactKind::kSelf: return cp_.self_friction;
      case collision::ContactKind::kTool: return cp_.tool_friction;
      case collision::ContactKind::kEnvironment: break;
    }
    return cp_.friction;
  }
  double damping() const { return cp_.damping; }

  /// The law on a contact's geometry at `relative` (the sphere's velocity minus the other side's
  /// at the contact). A pair apart acts only if it closes enough to touch within speculative_h
  /// (the implicit sub-step; 0: never). Friction: the regularized law, or with stick_slip only
  /// the cone's normal force (StickSlipFriction adds the rest).
  ContactPenalty Evaluate(collision::ContactKind kind, const PairGeometry& geometry,
                          const Vec3& relative, double speculative_h, bool stick_slip) const {
    ContactPenalty p;
    static_cast<PairGeometry&>(p) = geometry;
    const double vn = relative.dot(p.normal);
    // A pair that is apart but closing fast enough to touch within the implicit step acts now:
    // its linearized spring k (depth + n.dq) then pushes from the moment of contact, instead of
    // the contact being found a step late and deep (which creates energy at every impact).
    const bool speculative = p.depth <= 0.0 && p.depth - speculative_h * vn > 0.0;
    if (p.depth <= 0.0 && !speculative) return p;
    // Penalty spring and damping along the normal.
    const double spring = At(p.depth).force;
    const double fn = spring - cp_.damping * vn;
    if (fn <= 0.0 && !speculative) return p;
    p.slip = relative - vn * p.normal;
    p.force = fn * p.normal;
    if (!stick_slip) {
      const double friction = Friction(kind) * std::max(fn, 0.0);
      p.force -= (friction / std::max(p.slip.norm(), kFrictionSlip)) * p.slip;
    } else {
      // The friction cone's normal force is the penalty spring's alone: an impact's damping
      // pushes for a sub-step, and a cone widened by it stored its closing speed in the stuck
      // springs.
      p.normal_force = std::min(fn, spring);
    }
    p.active = true;
    return p;
  }

 private:
  const ContactParams& cp_;
  double radius_;
};

}  // namespace viscera::mechanics
