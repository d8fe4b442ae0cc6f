#pragma once
/// All forces of the mechanical layer, assembled as generalized forces (France et al. 2005,
/// eq. 4): gravity, viscous friction, Provot springs, Terzopoulos stretching, attachments, the
/// mesentery and external point loads. Q_i += b_i(s) F for a force F applied at curve parameter s.
#include <span>

#include "mechanics/block_band.h"
#include "mechanics/model.h"
#include "mechanics/stretching_energy.h"

namespace viscera::mechanics {

class Interactions;

/// An external force (N) applied at curve parameter s (a probe, a tool, a test).
struct PointLoad {
  double s = 0.0;
  Vec3 force = Vec3::Zero();
};

/// Energies (J) of each term.
struct Energies {
  double kinetic = 0.0;
  double gravity = 0.0;     ///< m g h relative to z = 0 (for gravity along -z)
  double stretch = 0.0;     ///< stretch springs
  double bend = 0.0;        ///< bend springs
  double continuous = 0.0;  ///< Terzopoulos stretching energy
  double attachment = 0.0;  ///< attachment springs
  double mesentery = 0.0;   ///< the mesentery's taut tethers
  double contact = 0.0;     ///< penalty contacts and grasp springs
  double potential() const {
    return gravity + stretch + bend + continuous + attachment + mesentery + contact;
  }
  double total() const { return kinetic + potential(); }
};

/// The forces' linearization for implicit integration: K = -dF/dq, D = -dF/dqd, and a dense
/// rank-one stiffness rank1_coeff * u u^T (global stretching energy) kept apart.
struct ForceJacobians {
  BlockBand stiffness;
  BlockBand damping;
  Points rank1_u;
  double rank1_coeff = 0.0;
  void Resize(int num_points);
};

/// F (#N by 3) = generalized forces at (q, qd). Fills `energies` (potential terms only; see
/// KineticEnergy) and `jacobians` when given. Allocates nothing once scratch is sized.
/// `interactions` (contacts, tools) may be null.
void ComputeForces(const Model& model, const Points& q, const Points& qd,
                   std::span<const PointLoad> loads, StretchScratch* scratch, Points* F,
                   Energies* energies = nullptr, ForceJacobians* jacobians = nullptr,
                   Interactions* interactions = nullptr);

/// 1/2 sum over axes of qd^T M qd (J). `scratch` is #N by 3.
double KineticEnergy(const Model& model, const Points& qd, Points* scratch);

/// All energies of a state (allocates; for reporting, not for the hot path). Contact energy is
/// included when `interactions` is given (as left by the last step).
Energies ComputeEnergies(const Model& model, const Points& q, const Points& qd,
                         Interactions* interactions = nullptr);

}  // namespace viscera::mechanics
