#pragma once
/// Which contacts the impulses act on (docs/impacts.md): the pairs that would end a step deeper
/// than contacts.impact_depth at the speed of an impact, for the impact limiter before the
/// sub-steps (Limit), and the pairs the implicit solve holds at the end of a sub-step
/// (GatherEnd). Tools are never in a set: their coupling and the contact law hold them, and the
/// tip is integrated against its contacts so that it cannot tunnel. Allocates only when the
/// candidate list grows beyond its high-water mark.
#include <vector>

#include "collision/sphere_chain.h"
#include "collision/verlet_list.h"
#include "common/types.h"
#include "mechanics/contact_geometry.h"
#include "mechanics/contact_window.h"
#include "mechanics/impact_limiter.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

class ImpactSets {
 public:
  /// What the implicit solve's impulses hold at the end of a sub-step (the depth at its start
  /// minus h times the closing speed):
  /// kImpact: impacts (closing faster than the penalty stops) within impact_depth, never pushed
  ///   apart (their impulse stays in the velocity);
  /// kDepth: any pair within impact_depth + (10 % - impact_depth) / 4 of the radius (6.25 % with
  ///   the defaults), pushed back if deeper (a position correction only: the sphere chain's
  ///   re-placement along the arc length slides spheres into each other while an impact stretches
  ///   the tube).
  enum class EndConstraint { kImpact, kDepth };

  /// sphere_mass: one collision sphere's share of the tube's mass (kg). @pre model, chain,
  /// candidates and geometry outlive this; geometry follows candidates' list.
  ImpactSets(const Model& model, const collision::SphereChain& chain,
             const collision::VerletList& candidates, ContactGeometry* geometry,
             double sphere_mass);

  /// Closing speeds below this are the penalty's (m/s).
  double impact_speed() const { return impact_speed_; }

  /// Inelastic impulses on the pairs that would end the next h deeper than impact_depth moving
  /// at u: u changes, and so does v (if given: the velocity whose kinetic energy counts) by the
  /// same impulses. Says whether any pair took an impulse. `u_fastest`, when not negative, is
  /// the fastest sphere's speed at u as ChainKinematics::Gather found it (the same sums): a pile
  /// slower than any impact is then left without gathering the spheres' velocities again.
  bool Limit(double h, Points* u, Points* v, double u_fastest = -1.0);

  /// Collects the self and environment pairs that the end velocity v_check (#N by 3) leaves
  /// beyond `kind`'s bound. `first` starts a new set; later calls keep the pairs already in it,
  /// in the same order, and add the new ones. Each contact of the set gets its normal speed at
  /// v_base and its target. Returns whether the set grew (false when impact_depth or
  /// impact_constraints is off).
  bool GatherEnd(EndConstraint kind, double h, const Points& v_check, const Points& v_base,
                 bool first, std::vector<ImpactLimiter::Contact>* contacts);

  /// The chain moved: the velocities GatherEnd read from its last v_check no longer stand.
  void ChainMoved() { end_gathered_ = false; }

 private:
  Vec3 SphereVelocity(int sphere, const Points& v) const {
    return ContactWindow::Of(chain_.spheres()[sphere]).Gather(v);
  }
  // Each sphere's velocity at v into `out`; returns the largest speed.
  double GatherSpheres(const Points& v, std::vector<Vec3>* out) const;

  const Model& model_;
  const collision::SphereChain& chain_;
  const collision::VerletList& candidates_;
  ContactGeometry& geometry_;
  double radius_;
  double impact_speed_;
  ImpactLimiter limiter_;
  // Limit: the set (candidate indices), its contacts, each sphere's velocity at the round's u,
  // and the velocities before the impulses.
  std::vector<int> set_;
  std::vector<char> in_set_;
  std::vector<ImpactLimiter::Contact> contacts_;
  std::vector<Vec3> velocity_;
  Points u0_, v0_;
  // GatherEnd: its set, each sphere's velocity at v_check and the largest squared speed, valid
  // while end_gathered_ (the chain's configuration unchanged) for that v_check.
  std::vector<int> end_set_;
  std::vector<char> in_end_set_;
  std::vector<Vec3> end_velocity_;
  Points end_checked_;
  double end_fastest_ = 0.0;
  bool end_finite_ = true, end_gathered_ = false;
};

}  // namespace viscera::mechanics
