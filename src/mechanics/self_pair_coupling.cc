#include "mechanics/self_pair_coupling.h"

#include "mechanics/avx_clone.h"

namespace viscera::mechanics {

void SelfPairCoupling::Weigh(double ck, double cd) {
  for (Pair& pair : pairs_) pair.weighed = ck * pair.k + cd * pair.d;
}

VISCERA_AVX_CLONE void SelfPairCoupling::AddCommonModeTerms(const double* xd, double* yd) const {
  // Called at every CG product: each pair carries its windows, so this reads nothing else. The
  // x and y components go two at a time (one SSE2 register), z alone: the same products and
  // sums in the same order per component.
  using Pair2 = Eigen::Vector2d;
  using In2 = Eigen::Map<const Pair2>;
  using Out2 = Eigen::Map<Pair2>;
  for (const Pair& pair : pairs_) {
    const Vec3 common = GatherCommon(pair.a, pair.b, xd);  // (J_a + J_b) x
    const Mat3& m = pair.weighed;
    const double* mc = m.data();  // column-major
    const Pair2 f_xy = (In2(mc) * common(0) + In2(mc + 3) * common(1)) + In2(mc + 6) * common(2);
    const double f_z = (m(2, 0) * common(0) + m(2, 1) * common(1)) + m(2, 2) * common(2);
    // J_a^T f and J_b^T f, as ContactWindow::Scatter's entries but two at a time: at every CG
    // product its four lanes' shuffles cost more than they save.
    for (const ContactWindow* window : {&pair.a, &pair.b}) {
      double* y = yd + 3 * window->first;
      for (int i = 0; i < 4; ++i) {
        Out2(y + 3 * i) += window->w[i] * f_xy;
        y[3 * i + 2] += window->w[i] * f_z;
      }
    }
  }
}

}  // namespace viscera::mechanics
