#include "collision/sphere_chain.h"

#include <cmath>

#include "common/check.h"

namespace viscera::collision {

SphereChain::SphereChain(const spline::CatmullRom& curve, double rest_length, double radius)
    : curve_(curve), radius_(radius), table_(4) {
  ThrowUnless(radius > 0.0 && rest_length > 0.0, "sphere chain needs a positive radius and length");
  // One radius apart: neighbours overlap by half, so the chain has no gap a sphere could pass.
  const int count = std::max(2, static_cast<int>(std::ceil(rest_length / radius)) + 1);
  spacing_ = rest_length / (count - 1);
  spheres_.resize(count);
}

void SphereChain::Place(const Points& q) {
  table_.Build(curve_, q);
  const double total = table_.total_length();
  const int n = size();
  size_t interval = 0;
  for (int k = 0; k < n; ++k) {
    Sphere& sp = spheres_[k];
    sp.s = table_.ParameterAt(total * k / (n - 1), &interval);
    const spline::SegmentBasis b = curve_.BasisAt(sp.s);
    sp.first = b.first;
    sp.w = b.w;
  }
  UpdateCentres(q);
}

void SphereChain::UpdateCentres(const Points& q) {
  for (Sphere& sp : spheres_) {
    sp.centre = sp.w[0] * q.row(sp.first).transpose() + sp.w[1] * q.row(sp.first + 1).transpose() +
                sp.w[2] * q.row(sp.first + 2).transpose() +
                sp.w[3] * q.row(sp.first + 3).transpose();
  }
}

}  // namespace viscera::collision
