#include "mechanics/stretching_energy.h"

#include "mechanics/avx_clone.h"
#include "mechanics/simd_lanes.h"

#include <algorithm>

#include "spline/gauss_legendre.h"

namespace viscera::mechanics {
namespace {

using Rule = spline::GaussLegendre<4>;

using lanes::Load4;
using lanes::Splat;
using lanes::Store4;
using lanes::V4;

// Fills the node tangents and speeds of every segment (its 4 nodes in the lanes); returns the
// per-segment lengths' sum.
[[gnu::always_inline]] inline double EvaluateNodes(const Model& model, const Points& q,
                                                   StretchScratch* s) {
  const V4 weights{Rule::kWeights[0], Rule::kWeights[1], Rule::kWeights[2], Rule::kWeights[3]};
  double total = 0.0;
  for (int j = 0; j < model.num_segments(); ++j) {
    // dw is column-major: column a holds the 4 nodes' weights of window point a.
    const double* dw = model.NodeDerivatives(j).data();
    const double* w = q.row(model.curve().FirstIndex(j)).data();  // row-major: point a at w + 3a
    const V4 c0 = Load4(dw), c1 = Load4(dw + 4), c2 = Load4(dw + 8), c3 = Load4(dw + 12);
    // Eigen's association in dw.row(g) * window: x and y summed in order, z as two pairs.
    const V4 dx = ((c0 * Splat(w[0]) + c1 * Splat(w[3])) + c2 * Splat(w[6])) + c3 * Splat(w[9]);
    const V4 dy = ((c0 * Splat(w[1]) + c1 * Splat(w[4])) + c2 * Splat(w[7])) + c3 * Splat(w[10]);
    const V4 dz = (c0 * Splat(w[2]) + c1 * Splat(w[5])) + (c2 * Splat(w[8]) + c3 * Splat(w[11]));
    const V4 speed = lanes::Sqrt((dx * dx + dy * dy) + dz * dz);
    const lanes::Mask4 positive = speed > Splat(0.0);
    const V4 inv_speed =
        (V4)((lanes::Mask4)(Splat(1.0) / speed) & positive);  // 0 where the speed is not > 0
    const int node = 4 * j;
    Store4(&s->node_speed[node], speed);
    Store4(&s->node_inv_speed[node], inv_speed);
    Store4(&s->node_tangent_x[node], dx * inv_speed);
    Store4(&s->node_tangent_y[node], dy * inv_speed);
    Store4(&s->node_tangent_z[node], dz * inv_speed);
    const V4 weighted = weights * speed;
    total = (((total + weighted[0]) + weighted[1]) + weighted[2]) + weighted[3];
  }
  return total;
}

double SegmentLengthFromNodes(const StretchScratch& s, int j) {
  double l = 0.0;
  for (int g = 0; g < 4; ++g) l += Rule::kWeights[g] * s.node_speed[4 * j + g];
  return l;
}

Eigen::RowVector3d NodeTangent(const StretchScratch& s, int node) {
  return {s.node_tangent_x[node], s.node_tangent_y[node], s.node_tangent_z[node]};
}

// Adds coeff * dl_j/dq to out (#N by 3): row by row, each row's 4 node terms in node order (the
// additions into each row of a pass node by node, in their order; one load and store per row).
[[gnu::always_inline]] inline void AddSegmentGradient(const Model& model, const StretchScratch& s,
                                                      int j, double coeff, Points* out) {
  const Eigen::Matrix4d& dw = model.NodeDerivatives(j);
  const int f = model.curve().FirstIndex(j);
  Eigen::RowVector3d t[4];
  for (int g = 0; g < 4; ++g) t[g] = coeff * Rule::kWeights[g] * NodeTangent(s, 4 * j + g);
  for (int a = 0; a < 4; ++a) {
    Eigen::RowVector3d row = out->row(f + a);
    for (int g = 0; g < 4; ++g) row += dw(g, a) * t[g];
    out->row(f + a) = row;
  }
}

// The length Hessian's node weights b'_a(u_g) b'_b(u_g) of a segment's window pairs a <= b,
// each in all 4 lanes: one set per node-derivative matrix (the model has three: the first, the
// interior and the last segments'), rebuilt when the segments' matrix changes.
class PairWeights {
 public:
  const V4& operator()(int pair, int g) const { return w_[pair][g]; }
  // Node g's weights of pairs 4 k to 4 k + 3 (the last group's lanes 2 and 3 +0): the blocks'
  // last entries, four pairs per vector.
  const V4& Group(int k, int g) const { return group_[k][g]; }
  void For(const Eigen::Matrix4d& dw) {
    if (&dw == dw_) return;
    dw_ = &dw;
    int pair = 0;
    for (int k = 0; k < 3; ++k) {
      for (int g = 0; g < 4; ++g) group_[k][g] = Splat(0.0);
    }
    for (int a = 0; a < 4; ++a) {
      for (int b = a; b < 4; ++b, ++pair) {
        for (int g = 0; g < 4; ++g) {
          w_[pair][g] = Splat(dw(g, a) * dw(g, b));
          group_[pair / 4][g][pair % 4] = w_[pair][g][0];
        }
      }
    }
  }

 private:
  const Eigen::Matrix4d* dw_ = nullptr;
  V4 w_[10][4];
  V4 group_[3][4];
};

// K += coeff * d^2 l_j / dq^2 = coeff * sum_g w_g b'_a b'_b (I - t t^T) / |P'|, summed over the
// segment's nodes before its 10 blocks are written. Each block is built as the whole
// column-major 3x3 that AddSymmetric(f + a, f + b, 1.0, h) adds (its mirrored entries are the
// same products), 4 entries per vector: entries 0-3, 4-7 and 8.
[[gnu::always_inline]] inline void AddSegmentLengthHessian(const Model& model,
                                                           const StretchScratch& s, int j,
                                                           double coeff, PairWeights* weights,
                                                           BlockBand* K) {
  weights->For(model.NodeDerivatives(j));
  const PairWeights& w = *weights;
  const int f = model.curve().FirstIndex(j);
  // Each node's coeff w_g / |P'| (I - t t^T).
  lanes::Block9 p[4];
  for (int g = 0; g < 4; ++g) {
    const int node = 4 * j + g;
    if (s.node_speed[node] <= 0.0) {
      p[g] = {Splat(0.0), Splat(0.0), 0.0};
      continue;
    }
    const double c = coeff * Rule::kWeights[g] * s.node_inv_speed[node];
    const lanes::Block9 tt =
        lanes::OuterSelf(s.node_tangent_x[node], s.node_tangent_y[node], s.node_tangent_z[node]);
    p[g] = {Splat(c) * (lanes::kIdentityLo - tt.lo), Splat(c) * (lanes::kIdentityMid - tt.mid),
            c * (1.0 - tt.last)};
  }
  // The 10 blocks' last entries four pairs per vector (the same products and sums as a
  // block's own), rather than one scalar chain per block.
  alignas(32) double last[12];
  for (int k = 0; k < 3; ++k) {
    const V4 sum = ((w.Group(k, 0) * Splat(p[0].last) + w.Group(k, 1) * Splat(p[1].last)) +
                    w.Group(k, 2) * Splat(p[2].last)) +
                   w.Group(k, 3) * Splat(p[3].last);
    Store4(last + 4 * k, sum);
  }
  int pair = 0;
  for (int a = 0; a < 4; ++a) {
    for (int b = a; b < 4; ++b, ++pair) {
      const lanes::Block9 h{
          ((w(pair, 0) * p[0].lo + w(pair, 1) * p[1].lo) + w(pair, 2) * p[2].lo) +
              w(pair, 3) * p[3].lo,
          ((w(pair, 0) * p[0].mid + w(pair, 1) * p[1].mid) + w(pair, 2) * p[2].mid) +
              w(pair, 3) * p[3].mid,
          last[pair]};
      lanes::AddBlock(K, f + a, f + b, h);
    }
  }
}

}  // namespace

void StretchScratch::Resize(int num_points) {
  const int nodes = 4 * (num_points - 1);
  node_tangent_x.resize(nodes);
  node_tangent_y.resize(nodes);
  node_tangent_z.resize(nodes);
  node_speed.resize(nodes);
  node_inv_speed.resize(nodes);
  length_gradient.resize(num_points, 3);
}

double CurveLength(const Model& model, const Points& q, StretchScratch* scratch) {
  return EvaluateNodes(model, q, scratch);
}

VISCERA_AVX_CLONE double AddStretchingForces(const Model& model, const Points& q, StretchScratch* s,
                                             Points* F, BlockBand* K, Points* rank1_u,
                                             double* rank1_coeff) {
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
    for (int j = 0; j < model.num_segments(); ++j)
      AddSegmentGradient(model, *s, j, 1.0, &s->length_gradient);
    *F -= de_dl * s->length_gradient;
    if (K) {
      // Positive semi-definite parts only: a compressed curve gets no negative stiffness.
      const double c = std::max(0.0, de_dl);
      if (c > 0.0) {
        PairWeights weights;
        for (int j = 0; j < model.num_segments(); ++j)
          AddSegmentLengthHessian(model, *s, j, c, &weights, K);
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
  PairWeights weights;
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
        for (int a = 0; a < 4; ++a)
          g.row(a) += Rule::kWeights[n] * dw(n, a) * NodeTangent(*s, 4 * j + n);
      }
      for (int a = 0; a < 4; ++a) {
        for (int b = a; b < 4; ++b) K->Add(f + a, f + b, d2e_dl2 * g.row(a).transpose() * g.row(b));
      }
      const double c = std::max(0.0, de_dl);
      if (c > 0.0) AddSegmentLengthHessian(model, *s, j, c, &weights, K);
    }
  }
  return energy;
}

}  // namespace viscera::mechanics
