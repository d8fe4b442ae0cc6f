// The force kernels computed in SIMD lanes (src/mechanics/simd_lanes.h) against the scalar code
// they replaced, copied here: the same numbers bit for bit, on random curves, with K and F
// already holding random numbers (so that the order of the additions into them matters too).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include "mechanics/forces.h"
#include "mechanics/model.h"
#include "mechanics/spring_forces.h"
#include "mechanics/stretching_energy.h"
#include "spline/gauss_legendre.h"
#include "test_models.h"

namespace viscera::mechanics {
namespace {

namespace reference {

// The stretching energy's scalar code before its lanes (commit 9c51277), with its scratch.
struct Scratch {
  Points node_tangent;
  VecX node_speed;
  VecX node_inv_speed;
  Points length_gradient;
  explicit Scratch(int num_points) {
    const int nodes = 4 * (num_points - 1);
    node_tangent.resize(nodes, 3);
    node_speed.resize(nodes);
    node_inv_speed.resize(nodes);
    length_gradient.resize(num_points, 3);
  }
};

using Rule = spline::GaussLegendre<4>;

// Fills the node tangents and speeds of every segment; returns the per-segment lengths' sum.
double EvaluateNodes(const Model& model, const Points& q, Scratch* s) {
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

double SegmentLengthFromNodes(const Scratch& s, int j) {
  double l = 0.0;
  for (int g = 0; g < 4; ++g) l += Rule::kWeights[g] * s.node_speed(4 * j + g);
  return l;
}

// Adds coeff * dl_j/dq to out (#N by 3).
void AddSegmentGradient(const Model& model, const Scratch& s, int j, double coeff, Points* out) {
  const Eigen::Matrix4d& dw = model.NodeDerivatives(j);
  const int f = model.curve().FirstIndex(j);
  for (int g = 0; g < 4; ++g) {
    const Eigen::RowVector3d t = coeff * Rule::kWeights[g] * s.node_tangent.row(4 * j + g);
    for (int a = 0; a < 4; ++a) out->row(f + a) += dw(g, a) * t;
  }
}

// K += coeff * d^2 l_j / dq^2 = coeff * sum_g w_g b'_a b'_b (I - t t^T) / |P'|, summed over the
// segment's nodes before its 10 blocks are written.
void AddSegmentLengthHessian(const Model& model, const Scratch& s, int j, double coeff,
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
    const double x = s.node_tangent(node, 0), y = s.node_tangent(node, 1),
                 z = s.node_tangent(node, 2);
    p[g] = {c * (1.0 - x * x), c * (1.0 - y * y), c * (1.0 - z * z),
            c * (0.0 - x * y), c * (0.0 - x * z), c * (0.0 - y * z)};
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

double AddStretchingForces(const Model& model, const Points& q, Scratch* s, Points* F, BlockBand* K,
                           Points* rank1_u, double* rank1_coeff) {
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
        for (int a = 0; a < 4; ++a)
          g.row(a) += Rule::kWeights[n] * dw(n, a) * s->node_tangent.row(4 * j + n);
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

// The springs' scalar code before its lanes (commit 9c51277).
double AddSpringForces(std::span<const Spring> springs, const Points& q, const Points& qd,
                       Points* F, BlockBand* K, BlockBand* D) {
  double energy = 0.0;
  for (const Spring& sp : springs) {
    const Vec3 x = (q.row(sp.j) - q.row(sp.i)).transpose();
    const double l = x.norm();
    if (l <= 0.0) continue;        // coincident points: no direction to push along
    const double inv_l = 1.0 / l;  // one division, not four
    const Vec3 t = x * inv_l;
    const double stretch = l - sp.rest;
    energy += 0.5 * sp.stiffness * stretch * stretch;
    const double relative_speed = (qd.row(sp.j) - qd.row(sp.i)).dot(t.transpose());
    const Vec3 f = (sp.stiffness * stretch + sp.damping * relative_speed) * t;  // pulls i toward j
    F->row(sp.i) += f.transpose();
    F->row(sp.j) -= f.transpose();
    if (!K && !(D && sp.damping > 0.0)) continue;  // forces only (RK4, energies)
    // Both blocks are symmetric: h on the two diagonal blocks, -h between them.
    const Sym3 ttT{t.x() * t.x(), t.y() * t.y(), t.z() * t.z(),
                   t.x() * t.y(), t.x() * t.z(), t.y() * t.z()};
    if (K) {
      // k (t t^T + g (I - t t^T)), g the geometric part.
      const double geometric = std::max(0.0, 1.0 - sp.rest * inv_l);
      const double k = sp.stiffness, g = geometric;
      const Sym3 h{k * (ttT[0] + g * (1.0 - ttT[0])), k * (ttT[1] + g * (1.0 - ttT[1])),
                   k * (ttT[2] + g * (1.0 - ttT[2])), k * (ttT[3] - g * ttT[3]),
                   k * (ttT[4] - g * ttT[4]),         k * (ttT[5] - g * ttT[5])};
      K->AddSymmetric(sp.i, sp.i, 1.0, h);
      K->AddSymmetric(sp.j, sp.j, 1.0, h);
      K->AddSymmetric(sp.i, sp.j, -1.0, h);
    }
    if (D && sp.damping > 0.0) {
      // c ttT once for the three blocks: (-c) x is -(c x) bit for bit.
      const double c = sp.damping;
      const Sym3 d{c * ttT[0], c * ttT[1], c * ttT[2], c * ttT[3], c * ttT[4], c * ttT[5]};
      D->AddSymmetric(sp.i, sp.i, 1.0, d);
      D->AddSymmetric(sp.j, sp.j, 1.0, d);
      D->AddSymmetric(sp.i, sp.j, -1.0, d);
    }
  }
  return energy;
}

}  // namespace reference

Points RandomPoints(int n, double amplitude, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Points p(n, 3);
  for (int i = 0; i < n; ++i) p.row(i) << u(*rng), u(*rng), u(*rng);
  return p;
}

BlockBand RandomBand(int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  BlockBand b(n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < BlockBand::kWidth; ++d) {
      for (int e = 0; e < 9; ++e) b.block(i, d).data()[e] = u(*rng);
    }
  }
  return b;
}

bool SameBits(const Points& a, const Points& b) {
  return a.rows() == b.rows() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

bool SameBits(const BlockBand& a, const BlockBand& b) {
  for (int i = 0; i < a.n(); ++i) {
    for (int d = 0; d < BlockBand::kWidth; ++d) {
      if (std::memcmp(a.block(i, d).data(), b.block(i, d).data(), sizeof(double) * 9) != 0)
        return false;
    }
  }
  return true;
}

// A chain of n points along x, stretched by 1.3 and perturbed (so that every segment's length
// term is on and its Hessian is written); `coincident` puts 4 points on one spot (speed 0).
Model ChainModel(int n, ContinuousScope scope, unsigned seed) {
  ModelParams p = testing::StraightChain(n, 1.0, 1.3);
  p.initial_q = testing::Perturbed(p.initial_q, 0.3 / n, seed);
  p.continuous_stretch = 2.5;
  p.continuous_scope = scope;
  return Model(p);
}

TEST(ForceLanes, StretchingIsTheScalarCodeBitForBit) {
#if defined(__AVX__)
  GTEST_SKIP() << "the reference sums as Eigen's SSE2 code does; built for AVX "
                  "(VISCERA_NATIVE=ON), Eigen sums otherwise";
#endif
  for (const ContinuousScope scope : {ContinuousScope::kGlobal, ContinuousScope::kSegment}) {
    for (const int n : {4, 5, 6, 7, 12, 41}) {
      for (unsigned seed = 0; seed < 10; ++seed) {
        SCOPED_TRACE(::testing::Message()
                     << "scope " << static_cast<int>(scope) << " n " << n << " seed " << seed);
        const Model model = ChainModel(n, scope, seed);
        std::mt19937 rng(1000 * n + seed);
        Points q = model.params().initial_q + RandomPoints(n, 0.2 / n, &rng);
        if (seed == 9 && n >= 7) {
          for (int i = 2; i < 7; ++i)
            q.row(i).setZero();  // segments of exactly zero speed (not 1e-17)
        }
        const Points f0 = RandomPoints(n, 1.0, &rng);
        const BlockBand k0 = RandomBand(n, &rng);
        Points f = f0, f_ref = f0, u(n, 3), u_ref(n, 3);
        BlockBand k = k0, k_ref = k0;
        double c = -1.0, c_ref = -2.0;
        StretchScratch scratch;
        scratch.Resize(n);
        reference::Scratch scratch_ref(n);
        const double e = AddStretchingForces(model, q, &scratch, &f, &k, &u, &c);
        const double e_ref =
            reference::AddStretchingForces(model, q, &scratch_ref, &f_ref, &k_ref, &u_ref, &c_ref);
        EXPECT_EQ(std::memcmp(&e, &e_ref, sizeof e), 0);
        EXPECT_EQ(std::memcmp(&c, &c_ref, sizeof c), 0);
        EXPECT_TRUE(SameBits(f, f_ref));
        EXPECT_TRUE(SameBits(k, k_ref));
        if (scope == ContinuousScope::kGlobal) {
          EXPECT_TRUE(SameBits(u, u_ref));
        }
        if (seed != 9) {
          EXPECT_FALSE(SameBits(k, k0));  // the Hessian was written
        }
      }
    }
  }
}

TEST(ForceLanes, SpringsAreTheScalarCodeBitForBit) {
  for (const int n : {2, 5, 30}) {
    for (unsigned seed = 0; seed < 10; ++seed) {
      SCOPED_TRACE(::testing::Message() << "n " << n << " seed " << seed);
      std::mt19937 rng(77 * n + seed);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      Points q = RandomPoints(n, 1.0, &rng);
      const Points qd = RandomPoints(n, 1.0, &rng);
      if (seed == 0 && n > 2) q.row(1) = q.row(0);  // coincident points: their springs are skipped
      std::vector<Spring> springs;
      for (int k = 0; k < 4 * n;
           ++k) {  // random pairs at most 3 apart, both orders, repeated blocks
        const int i = std::min(n - 1, static_cast<int>(u(rng) * n));
        const int j = std::clamp(i + static_cast<int>(u(rng) * 7) - 3, 0, n - 1);
        if (i == j) continue;
        Spring sp;
        sp.i = i;
        sp.j = j;
        sp.rest = 2.0 * u(rng);  // some compressed (geometric part clamped), some stretched
        sp.stiffness = 10.0 * u(rng);
        sp.damping = k % 3 == 0 ? 0.0 : u(rng);
        springs.push_back(sp);
      }
      for (const bool with_d : {false, true}) {
        const Points f0 = RandomPoints(n, 1.0, &rng);
        const BlockBand k0 = RandomBand(n, &rng), d0 = RandomBand(n, &rng);
        Points f = f0, f_ref = f0;
        BlockBand k = k0, k_ref = k0, d = d0, d_ref = d0;
        const double e = AddSpringForces(springs, q, qd, &f, &k, with_d ? &d : nullptr);
        const double e_ref =
            reference::AddSpringForces(springs, q, qd, &f_ref, &k_ref, with_d ? &d_ref : nullptr);
        EXPECT_EQ(std::memcmp(&e, &e_ref, sizeof e), 0);
        EXPECT_TRUE(SameBits(f, f_ref));
        EXPECT_TRUE(SameBits(k, k_ref));
        EXPECT_TRUE(SameBits(d, d_ref));
        EXPECT_FALSE(SameBits(k, k0));
      }
    }
  }
}

// ComputeForces' viscous friction (row by row) against the scatter pass it replaced, on random
// velocities with every other force off; and its damping band, copied from the model's.
TEST(ForceLanes, ViscousFrictionIsTheScatterPassBitForBit) {
  for (const int n : {4, 5, 9, 40}) {
    SCOPED_TRACE(n);
    ModelParams p = testing::StraightChain(n);
    p.damping = 1.7;
    p.gravity = Vec3(0.3, -0.2, -9.81);
    const Model model(p);
    std::mt19937 rng(n);
    const Points qd = RandomPoints(n, 1.0, &rng);
    Points expected = model.gravity_force();
    const Band& m = model.mass_band();
    for (int i = 0; i < n; ++i) {
      expected.row(i) -= p.damping * m(i, 0) * qd.row(i);
      for (int d = 1; d <= kHalfBand && i + d < n; ++d) {
        expected.row(i) -= p.damping * m(i, d) * qd.row(i + d);
        expected.row(i + d) -= p.damping * m(i, d) * qd.row(i);
      }
    }
    StretchScratch scratch;
    scratch.Resize(n);
    ForceJacobians jac;
    jac.Resize(n);
    jac.stiffness = RandomBand(n, &rng);
    jac.damping = RandomBand(n, &rng);
    Points f(n, 3);
    ComputeForces(model, p.initial_q, qd, {}, &scratch, &f, nullptr, &jac);
    EXPECT_TRUE(SameBits(f, expected));
    EXPECT_TRUE(SameBits(jac.damping, model.viscous_damping()));
    EXPECT_TRUE(SameBits(jac.stiffness, BlockBand(n)));
  }
}

}  // namespace
}  // namespace viscera::mechanics
