#pragma once
// Small models for mechanics tests.
#include <cmath>
#include <random>

#include "mechanics/model_params.h"

namespace viscera::mechanics::testing {

/// A straight chain of n control points along +x from the origin, `stretch` times its rest
/// length, with every stiffness off and no gravity. Tests switch on what they need.
inline ModelParams StraightChain(int n, double length = 1.0, double stretch = 1.0) {
  ModelParams p;
  p.length = length;
  p.radius = 0.0125;
  p.mass = 0.5;
  p.gravity = Vec3::Zero();
  p.initial_q.resize(n, 3);
  for (int i = 0; i < n; ++i) p.initial_q.row(i) << stretch * length * i / (n - 1), 0.0, 0.0;
  return p;
}

/// Random perturbation of the rows (m), fixed seed.
inline Points Perturbed(const Points& q, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-amplitude, amplitude);
  Points out = q;
  for (int i = 0; i < out.rows(); ++i)
    out.row(i) += Eigen::RowVector3d(uni(rng), uni(rng), uni(rng));
  return out;
}

}  // namespace viscera::mechanics::testing
