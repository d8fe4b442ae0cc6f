#pragma once
/// ChainKinematics: the sphere chain where the tube's configuration puts it, and its spheres'
/// velocities, each redone only when q or q̇ changes (a sub-step's several force evaluations, the
/// tools' advance and the step's end often ask for the same). Interactions owns it; what depends
/// on where the spheres are (the narrow phase, the impact sets) it invalidates when Configure says
/// the chain moved.
#include <vector>

#include "collision/sphere_chain.h"
#include "common/types.h"
#include "mechanics/contact_window.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

class ChainKinematics {
 public:
  explicit ChainKinematics(const Model& model);

  const collision::SphereChain& chain() const { return chain_; }
  /// The generalized-force map of sphere `sphere` (its control points' weights).
  ContactWindow Window(int sphere) const { return ContactWindow::Of(chain_.spheres()[sphere]); }

  /// The chain at q: re-placed along its arc length if `place`, else its spheres moved with the
  /// curve (spheres that follow the material are placed once, at the first configuration). Returns
  /// whether the chain moved: false, doing nothing, for the configuration it already has.
  bool Configure(const Points& q, bool place);
  /// The spheres' velocities at q̇ (#N by 3), with the chain as last configured.
  void Gather(const Points& qd);
  /// Sphere `sphere`'s velocity, and the largest speed (m/s), as last gathered.
  const Vec3& velocity(int sphere) const { return velocity_[sphere]; }
  double fastest() const { return fastest_; }
  /// fastest() if the velocities were last gathered at qd (and the chain not moved since),
  /// else -1.
  double FastestAt(const Points& qd) const { return GatheredAt(qd) ? fastest_ : -1.0; }

 private:
  // The velocities were last gathered at qd (and the chain not moved since).
  bool GatheredAt(const Points& qd) const {
    return gathered_ && qd.rows() == gathered_qd_.rows() &&
           (qd.array() == gathered_qd_.array()).all();
  }

  collision::SphereChain chain_;
  bool follow_material_;  // params().contacts.spheres_follow_material
  Points configured_q_, gathered_qd_;
  bool configured_ = false, placed_ = false, gathered_ = false;
  std::vector<Vec3> velocity_;
  double fastest_ = 0.0;  // m/s, the largest of velocity_
};

}  // namespace viscera::mechanics
