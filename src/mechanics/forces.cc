#include "mechanics/forces.h"

#include <algorithm>

#include "mechanics/attachment_forces.h"
#include "mechanics/interactions.h"
#include "mechanics/mesentery_forces.h"
#include "mechanics/spring_forces.h"

namespace viscera::mechanics {

void ForceJacobians::Resize(int num_points) {
  stiffness.Resize(num_points);
  damping.Resize(num_points);
  rank1_u.setZero(num_points, 3);
  rank1_coeff = 0.0;
}

void ComputeForces(const Model& model, const Points& q, const Points& qd,
                   std::span<const PointLoad> loads, StretchScratch* scratch, Points* F,
                   Energies* energies, ForceJacobians* jac, Interactions* interactions) {
  BlockBand* K = jac ? &jac->stiffness : nullptr;
  BlockBand* D = jac ? &jac->damping : nullptr;
  if (jac) {
    K->SetZero();
    D->Assign(model.viscous_damping());  // same size: one copy
  }

  // Gravity: constant generalized force; E = -sum_i Q_i . q_i (= m g h for g along -z).
  *F = model.gravity_force();
  if (energies) energies->gravity = -(model.gravity_force().array() * q.array()).sum();

  // Viscous friction: force density -gamma rho dP/dt, i.e. Q = -gamma M qd. Row by row, each
  // row's terms subtracted in the order of a pass over the band's upper entries that scatters
  // both halves (M(r - d, d) qd_(r-d) for d = 3, 2, 1, then M(r, d) qd_(r+d) for d = 0 .. 3):
  // the same numbers, one load and store per row.
  const double gamma = model.params().damping;
  if (gamma > 0.0) {
    const Band& m = model.mass_band();
    const int n = model.num_points();
    for (int r = 0; r < n; ++r) {
      Eigen::RowVector3d row = F->row(r);
      for (int d = std::min(r, kHalfBand); d >= 1; --d) row -= gamma * m(r - d, d) * qd.row(r - d);
      for (int d = 0; d <= kHalfBand && r + d < n; ++d) row -= gamma * m(r, d) * qd.row(r + d);
      F->row(r) = row;
    }
  }

  const double e_stretch = AddSpringForces(model.stretch_springs(), q, qd, F, K, D);
  const double e_bend = AddSpringForces(model.bend_springs(), q, qd, F, K, D);
  const double e_continuous = AddStretchingForces(
      model, q, scratch, F, K, jac ? &jac->rank1_u : nullptr, jac ? &jac->rank1_coeff : nullptr);
  const double e_attachment = AddAttachmentForces(model.attachments(), q, qd, F, K, D);
  const double e_mesentery = AddMesenteryForces(model.tethers(), q, qd, F, K, D);
  for (const PointLoad& load : loads) model.curve().AddForce(load.s, load.force, F);
  const double e_contact = interactions ? interactions->AddForces(q, qd, F, K, D) : 0.0;

  if (energies) {
    energies->stretch = e_stretch;
    energies->bend = e_bend;
    energies->continuous = e_continuous;
    energies->attachment = e_attachment;
    energies->mesentery = e_mesentery;
    energies->contact = e_contact;
  }
}

double KineticEnergy(const Model& model, const Points& qd, Points* scratch) {
  BandMultiply(model.mass_band(), qd, scratch);
  return 0.5 * (qd.array() * scratch->array()).sum();
}

Energies ComputeEnergies(const Model& model, const Points& q, const Points& qd,
                         Interactions* interactions) {
  StretchScratch scratch;
  scratch.Resize(model.num_points());
  Points f(model.num_points(), 3);
  Energies e;
  ComputeForces(model, q, qd, {}, &scratch, &f, &e, nullptr, interactions);
  e.kinetic = KineticEnergy(model, qd, &f);
  return e;
}

}  // namespace viscera::mechanics
