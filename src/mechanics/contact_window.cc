#include "mechanics/contact_window.h"

#include "mechanics/avx_clone.h"

namespace viscera::mechanics {

VISCERA_AVX_CLONE void ContactWindow::AddOuter(const Mat3& k, const Mat3* d, BlockBand* K,
                                               BlockBand* D) const {
  // The window's 10 upper blocks, K's and D's in one pass, by their symmetric entries.
  const Sym3 ks = ToSym3(k);
  const Sym3 ds = d ? ToSym3(*d) : Sym3{};
  contact_window::AddOuter(first, w, ks, d ? &ds : nullptr, K, D);
}

}  // namespace viscera::mechanics
