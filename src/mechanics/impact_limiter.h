#pragma once
/// Inelastic impacts at the velocity level (Bridson, Fedkiw & Anderson 2002 for cloth; Box2D's
/// speculative contacts): before a sub-step, every contact that would end the sub-step deeper
/// than an allowed depth if it kept its velocity gets an impulse along its normal that removes
/// just the excess closing speed, never more (no bounce, never a push apart). The penalty law
/// keeps handling resting contact; this only catches what it cannot stop in time (a coil landing
/// at 3 m/s would need ~20 kN/m per sphere to stop within 10 % of the radius).
///
/// The impulses are solved together (projected Gauss-Seidel on the contacts' Delassus matrix
/// J M^-1 J^T, with M the tube's consistent mass matrix and its pins), so a sphere caught
/// between two contacts is not pushed by one into the other. Kinetic energy can only decrease:
/// the exact solution removes Λ^T J v' - Λ^T G Λ / 2 ≤ 0, and a truncated iteration is scaled
/// back if it would not. Allocates only when a larger impact than any before needs more room.
#include <vector>

#include "collision/sphere_chain.h"
#include "mechanics/incremental_delassus.h"
#include "mechanics/mass_solver.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

class ImpactLimiter {
 public:
  /// One contact about to end deeper than allowed: sphere a against sphere b (b < 0: an obstacle
  /// or a tool, of infinite mass), the normal pointing toward a, the normal relative velocity
  /// (negative: closing) and the least it may be after the impulse (≤ 0).
  struct Contact {
    int a = 0, b = -1;
    Vec3 normal = Vec3::UnitZ();
    double normal_speed = 0.0;
    double target = 0.0;
    double energy_speed = 0.0;  // the normal speed of the velocity whose kinetic energy counts
  };

  explicit ImpactLimiter(const Model& model, int spheres);

  /// Forgets the spheres' solved columns: call whenever the chain has moved.
  void Reset();

  /// Finds the impulses that bring every contact's normal speed up to its target (or leave it
  /// where it is if it already is) and adds their velocity change to u (#N by 3) and to v (if
  /// given), never so much that v's kinetic energy grows. Returns the energy removed from v (J).
  double Apply(const std::vector<Contact>& contacts, const collision::SphereChain& chain, Points* u,
               Points* v);

 private:
  // Column slot of sphere s in y_ (M^-1 applied to its basis weights), solved on first use.
  int Slot(int sphere);
  void SolvePending(const collision::SphereChain& chain);
  // w_s^T M^-1 w_t for two spheres with slots.
  double Coupling(int s, int t, const collision::SphereChain& chain) const;

  const Model& model_;
  MassSolver mass_;
  double immobile_;                        // 1/kg: a contact this hard to move is pinned
  Points columns_;                         // three spheres' weights at a time, solved in place
  MatX y_;                                 // #N by slots: M^-1 w_s per involved sphere
  std::vector<int> slot_of_;               // per sphere, -1 when not involved
  std::vector<int> sphere_of_;             // per slot
  std::vector<int> pending_;               // slots not solved yet
  IncrementalDelassus<Contact> delassus_;  // kept while the spheres' columns stand (until Reset)
  VecX lambda_, speed_, target_;
  std::vector<Vec3> impulse_;  // per slot
};

}  // namespace viscera::mechanics
