#include "mechanics/chain_kinematics.h"

#include "mechanics/avx_clone.h"

#include <algorithm>
#include <cmath>

namespace viscera::mechanics {

ChainKinematics::ChainKinematics(const Model& model)
    : chain_(model.curve(), model.params().length, model.params().radius),
      follow_material_(model.params().contacts.spheres_follow_material) {
  velocity_.assign(chain_.size(), Vec3::Zero());
}

bool ChainKinematics::Configure(const Points& q, bool place) {
  if (follow_material_ && configured_) place = false;
  const bool same = configured_ && (placed_ || !place) && q.rows() == configured_q_.rows() &&
                    (q.array() == configured_q_.array()).all();
  if (same) return false;
  if (place) {
    chain_.Place(q);
  } else {
    chain_.UpdateCentres(q);
  }
  configured_q_ = q;  // same size after the first: no allocation
  configured_ = true;
  placed_ = place;
  gathered_ = false;  // the spheres' weights may have changed
  return true;
}

VISCERA_AVX_CLONE void ChainKinematics::Gather(const Points& qd) {
  if (GatheredAt(qd)) return;
  double fastest = 0.0;
  for (int k = 0; k < chain_.size(); ++k) {
    velocity_[k] = Window(k).Gather(qd);
    fastest = std::max(fastest, velocity_[k].squaredNorm());
  }
  fastest_ = std::sqrt(fastest);
  gathered_qd_ = qd;
  gathered_ = true;
}

}  // namespace viscera::mechanics
