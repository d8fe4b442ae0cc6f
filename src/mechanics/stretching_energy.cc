#include "mechanics/stretching_energy.h"

#include "mechanics/avx_clone.h"

#include <algorithm>

#include "spline/gauss_legendre.h"

namespace viscera::mechanics {
namespace {

using Rule = spline::GaussLegendre<4>;

// Fills the node tangents and speeds of every segment; returns the per-segment lengths' sum.
[[gnu::always_inline]] inline double EvaluateNodes(const Model& model, const Points& q, StretchScratch* s) {
  double total = 0.0;
  for (int j = 0; j < model.num_segments(); ++j) {
    const Eigen::Matrix4d& dw = model.NodeDerivatives(j);
    const auto window = q.middleRows<4>(model.curve().FirstIndex(j));
    for (int g = 0; g < 4; ++g) {
      const Eigen::RowVector3d d = dw.row(g) * window;
      const double speed = d.norm();
      const int node = 4 * j + g;
      const double inv_speed = speed > 0.0 ? 1.0 / speed : 0.0;  // one division per node
      s->node_speed(node) = speed;
      s->node_inv_speed(node) = inv_speed;
      s->node_tangent.row(node) = d * inv_speed;
      total += Rule::kWeights[g] * speed;
    }
  }
  return total;
}

double SegmentLengthFromNodes(const StretchScratch& s, int j) {
  double l = 0.0;
  for (int g = 0; g < 4; ++g) l += Rule::kWeights[g] * s.node_speed(4 * j + g);
  return l;
}

// Adds coeff * dl_j/dq to out (#N by 3).
[[gnu::always_inline]] inline void AddSegmentGradient(const Model& model, const StretchScratch& s, int j, double coeff, Points* out) {
  const Eigen::Matrix4d& dw = model.NodeDerivatives(j);
  const int f = model.curve().FirstIndex(j);
  for (int g = 0; g < 4; ++g) {
    const Eigen::RowVector3d t = coeff * Rule::kWeights[g] * s.node_tangent.row(4 * j + g);
    for (int a = 0; a < 4; ++a) out->row(f + a) += dw(g, a) * t;
  }
}

// K += coeff * d^2 l_j / dq^2 = coeff * sum_g w_g b'_a b'_b (I - t t^T) / |P'|, summed over the
// segment's nodes before its 10 blocks are written.
[[gnu::always_inline]] inline void AddSegmentLengthHessian(const Model& model, const StretchScratch& s, int j, double coeff,
                             BlockBand* K) {
  const Eigen::Matrix4d& dw = model.NodeDerivatives(j);
  const int f = model.curve().FirstIndex(j);
  // Each node's coeff w_g / |P'| (I - t t^T), by its symmetric entries.
  Sym3 p[4];
  for (int g = 0; g < 4; ++g) {
    const int node = 4 * j + g;
    if (s.node_speed(node) <= 0.0) {
      p[g].fill(0.0);
      continue;
    }
    const double c = coeff * Rule::kWeights[g] * s.node_inv_speed(node);
    const double x = s.node_tangent(node, 0), y = s.node_tangent(node, 1), z = s.node_tangent(node, 2);
    p[g] = {c * (1.0 - x * x), c * (1.0 - y * y), c * (1.0 - z * z), c * (0.0 - x * y), c * (0.0 - x * z), c * (0.0 - y * z)};
  }
  for (int a = 0; a < 4; ++a) {
    for (int b = a; b < 4; ++b) {
      Sym3 h;
      const double w0 = dw(0, a) * dw(0, b);
      for (int e = 0; e < 6; ++e) h[e] = w0 * p[0][e];
      for (int g = 1; g < 4; ++g) {
        const double wg = dw(g, a) * dw(g, b);
        for (int e = 0; e < 6; ++e) h[e] += wg * p[g][e];
      }
      K->AddSymmetric(f + a, f + b, 1.0, h);
    }
  }
}

}  // namespace

void StretchScratch::Resize(int num_points) {
  const int nodes = 4 * (num_points - 1);
  node_tangent.resize(nodes, 3);
  node_speed.resize(nodes);
  node_inv_speed.resize(nodes);
  length_gradient.resize(num_points, 3);
}

double CurveLength(const Model& model, const Points& q, StretchScratch* scratch) {
  return EvaluateNodes(model, q, scratch);
}

VISCERA_AVX_CLONE double AddStretchingForces(const Model& model, const Points& q, StretchScratch* s, Points* F,
                           BlockBand* K, Points* rank1_u, double* rank1_coeff) {
  const double k = model.params().continuous_stretch;
  if (rank1_coeff) *rank1_coeff = 0.0;
  if (k <= 0.0) return 0.0;
  const double length = EvaluateNodes(model, q, s);

  if (model.params().continuous_scope == ContinuousScope::kGlobal) {
    const double l0 = model.params().length;
    const double lambda = length / l0;
    const double strain = lambda * lambda - 1.0;
    // dE/dl and d2E/dl2 of E = k/2 (lambda^2 - 1)^2.
    const double de_dl = 2.0 * k * strain * lambda / l0;
    const double d2e_dl2 = 2.0 * k * (3.0 * lambda * lambda - 1.0) / (l0 * l0);
    s->length_gradient.setZero();
    for (int j = 0; j < model.num_segments(); ++j) AddSegmentGradient(model, *s, j, 1.0, &s->length_gradient);
    *F -= de_dl * s->length_gradient;
    if (K) {
      // Positive semi-definite parts only: a compressed curve gets no negative stiffness.
      const double c = std::max(0.0, de_dl);
      if (c > 0.0) {
        for (int j = 0; j < model.num_segments(); ++j) AddSegmentLengthHessian(model, *s, j, c, K);
      }
      if (rank1_u && rank1_coeff) {
        *rank1_u = s->length_gradient;
        *rank1_coeff = std::max(0.0, d2e_dl2);
      }
    }
    return 0.5 * k * strain * strain;
  }

  // Segment scope: every segment is its own spring of energy k_j/2 (lambda_j^2 - 1)^2.
  const double l0 = model.rest_segment_length();
  const double kj = k / model.num_segments();
  double energy = 0.0;
  for (int j = 0; j < model.num_segments(); ++j) {
    const double lambda = SegmentLengthFromNodes(*s, j) / l0;
    const double strain = lambda * lambda - 1.0;
    energy += 0.5 * kj * strain * strain;
    const double de_dl = 2.0 * kj * strain * lambda / l0;
    AddSegmentGradient(model, *s, j, -de_dl, F);
    if (K) {
      const double d2e_dl2 = std::max(0.0, 2.0 * kj * (3.0 * lambda * lambda - 1.0) / (l0 * l0));
      // Rank-one part, local to the segment's window: d2e_dl2 * g g^T with g = dl_j/dq.
      const Eigen::Matrix4d& dw = model.NodeDerivatives(j);
      const int f = model.curve().FirstIndex(j);
      Eigen::Matrix<double, 4, 3> g = Eigen::Matrix<double, 4, 3>::Zero();
      for (int n = 0; n < 4; ++n) {
        for (int a = 0; a < 4; ++a) g.row(a) += Rule::kWeights[n] * dw(n, a) * s->node_tangent.row(4 * j + n);
      }
      for (int a = 0; a < 4; ++a) {
        for (int b = a; b < 4; ++b) K->Add(f + a, f + b, d2e_dl2 * g.row(a).transpose() * g.row(b));
      }
      const double c = std::max(0.0, de_dl);
      if (c > 0.0) AddSegmentLengthHessian(model, *s, j, c, K);
    }
  }
  return energy;
}

}  // namespace viscera::mechanics
