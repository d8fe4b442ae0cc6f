#include "mechanics/model.h"

#include <cmath>

#include "common/check.h"
#include "mechanics/mass_matrix.h"
#include "spline/gauss_legendre.h"

namespace viscera::mechanics {
namespace {

void RequirePositive(const char* name, double value) {
  ThrowUnless(std::isfinite(value) && value > 0.0, name, " = ", value,
              ": must be a finite number > 0");
}

void RequireNonNegative(const char* name, double value) {
  ThrowUnless(std::isfinite(value) && value >= 0.0, name, " = ", value,
              ": must be a finite number >= 0");
}

void ValidateMesentery(const MesenteryParams& m) {
  ThrowUnless(m.root_start.allFinite() && m.root_end.allFinite(),
              "mesentery.root_start, root_end must be finite");
  RequirePositive("mesentery.stiffness", m.stiffness);
  RequireNonNegative("mesentery.damping", m.damping);
  RequireNonNegative("mesentery.onset", m.onset);
  RequireNonNegative("mesentery extra slack", m.extra_slack);
  ThrowUnless(m.tethers == 0 || m.tethers >= 2, "mesentery.tethers = ", m.tethers,
              ": must be 0 (one per control point) or >= 2");
  ThrowUnless(m.lengths.size() >= 2,
              "mesentery.lengths: need at least two [s, length] pairs, from s = 0 to s = 1");
  ThrowUnless(m.lengths.front().first == 0.0 && m.lengths.back().first == 1.0,
              "mesentery.lengths: s must run from 0 to 1, got ", m.lengths.front().first, " to ",
              m.lengths.back().first);
  for (size_t i = 0; i < m.lengths.size(); ++i) {
    const auto [s, l] = m.lengths[i];
    ThrowUnless(std::isfinite(l) && l > 0.0, "mesentery.lengths: length ", l, " at s = ", s,
                ": must be a finite number > 0");
    if (i == 0) continue;  // (the message's arguments are evaluated whatever the condition)
    ThrowUnless(s > m.lengths[i - 1].first, "mesentery.lengths: s = ", s,
                " after s = ", m.lengths[i - 1].first, ": s must increase");
  }
}

void Validate(const ModelParams& p) {
  RequirePositive("simulation.rate_hz", p.rate_hz);
  ThrowUnless(p.substeps >= 1, "simulation.substeps = ", p.substeps, ": must be >= 1");
  ThrowUnless(p.cg_iteration_cap >= 0, "cg_iteration_cap = ", p.cg_iteration_cap, ": must be >= 0");
  ThrowUnless(p.gravity.allFinite(), "simulation.gravity must be finite");
  RequirePositive("intestine.length", p.length);
  RequirePositive("intestine.radius", p.radius);
  RequirePositive("intestine.mass", p.mass);
  RequireNonNegative("intestine.stretch_stiffness", p.stretch_stiffness);
  RequireNonNegative("intestine.bend_stiffness", p.bend_stiffness);
  ThrowUnless(std::isfinite(p.bend_reference_curvature),
              "intestine.bend_reference_curvature = ", p.bend_reference_curvature,
              ": must be finite");
  RequireNonNegative("intestine.continuous_stretch", p.continuous_stretch);
  RequireNonNegative("intestine.damping", p.damping);
  RequireNonNegative("intestine.spring_damping", p.spring_damping);
  ThrowUnless(p.initial_q.rows() >= 4, "intestine.control_points = ", p.initial_q.rows(),
              ": need at least 4");
  ThrowUnless(p.initial_q.allFinite(), "the starting control points must be finite");
  for (double s : p.pinned) {
    ThrowUnless(std::isfinite(s) && s >= 0.0 && s <= 1.0, "intestine.pinned: ", s,
                " is not a curve parameter in [0, 1]");
  }
  for (const AttachmentParams& a : p.attachments) {
    ThrowUnless(std::isfinite(a.s) && a.s >= 0.0 && a.s <= 1.0, "attachment.at = ", a.s,
                ": must be a curve parameter in [0, 1]");
    ThrowUnless(!a.point || a.point->allFinite(), "attachment.point must be finite");
    RequireNonNegative("attachment.stiffness", a.stiffness);
    RequireNonNegative("attachment.damping", a.damping);
    RequireNonNegative("attachment.rest_length", a.rest_length);
  }
  if (p.mesentery) {
    ValidateMesentery(*p.mesentery);
    // more tethers than that add nothing (each one acts through a window of 4 control points)
    ThrowUnless(p.mesentery->tethers <= 4 * p.initial_q.rows(),
                "mesentery.tethers = ", p.mesentery->tethers, ": at most 4 per control point (",
                4 * p.initial_q.rows(), ")");
  }
}

}  // namespace

Model::Model(ModelParams params)
    : params_((Validate(params), std::move(params))),
      curve_(static_cast<int>(params_.initial_q.rows())) {
  mass_band_ = BuildMassBand(curve_, params_.mass);
  mass_factor_.Factor(mass_band_);
  viscous_damping_.Resize(num_points());
  if (params_.damping > 0.0) {
    // As ComputeForces added it to a zeroed band at every evaluation: the same numbers.
    const double gamma = params_.damping;
    for (int i = 0; i < num_points(); ++i) {
      for (int d = 0; d <= kHalfBand && i + d < num_points(); ++d) {
        viscous_damping_.block(i, d) += gamma * mass_band_(i, d) * Mat3::Identity();
      }
    }
  }
  mass_shares_ = MassRowSums(mass_band_);
  gravity_force_.resize(num_points(), 3);
  for (int i = 0; i < num_points(); ++i)
    gravity_force_.row(i) = mass_shares_(i) * params_.gravity.transpose();

  using Rule = spline::GaussLegendre<4>;
  auto node_dw = [&](int segment) {
    Eigen::Matrix4d dw;
    for (int g = 0; g < 4; ++g) {
      const spline::SegmentBasis b = curve_.Basis(segment, Rule::kNodes[g]);
      for (int a = 0; a < 4; ++a) dw(g, a) = b.dw[a];
    }
    return dw;
  };
  node_dw_first_ = node_dw(0);
  node_dw_interior_ = node_dw(1);
  node_dw_last_ = node_dw(num_segments() - 1);

  BuildSprings();
  for (const AttachmentParams& a : params_.attachments) {
    Attachment att;
    att.at = MakeCurvePoint(a.s);
    att.anchor = a.point ? *a.point : Evaluate(att.at, params_.initial_q);
    att.stiffness = a.stiffness;
    att.damping = a.damping;
    att.rest_length = a.rest_length;
    attachments_.push_back(att);
  }
  BuildPins();
  BuildTethers();
}

void Model::BuildTethers() {
  if (!params_.mesentery) return;
  const MesenteryParams& m = *params_.mesentery;
  const int count = m.tethers > 0 ? m.tethers : num_points();
  for (int k = 0; k < count; ++k) {
    const double s = static_cast<double>(k) / (count - 1);
    // each tether holds its share of the tube (trapezoid rule: half at the ends)
    const double share = params_.length / (count - 1) * (k == 0 || k == count - 1 ? 0.5 : 1.0);
    size_t j = 1;
    while (j + 1 < m.lengths.size() && m.lengths[j].first < s) ++j;
    const auto [s0, l0] = m.lengths[j - 1];
    const auto [s1, l1] = m.lengths[j];
    Tether t;
    t.at = MakeCurvePoint(s);
    t.root = m.root_start + s * (m.root_end - m.root_start);
    t.length = l0 + (s - s0) / (s1 - s0) * (l1 - l0) + m.extra_slack;
    t.stiffness = m.stiffness * share;
    t.damping = m.damping * share;
    t.onset = m.onset;
    tethers_.push_back(t);
  }
}

void Model::BuildSprings() {
  const int n = num_points();
  const double l0 = rest_segment_length();
  const double kappa_ref = params_.bend_reference_curvature > 0.0 ? params_.bend_reference_curvature
                                                                  : 1.0 / params_.radius;
  // Bend springs (i, i+2): on an arc of curvature kappa the chord over 2 l0 shortens by
  // kappa^2 l0^3 / 3, so the spring energy per unit length is k_b kappa^4 l0^5 / 18. Equal to the
  // rod's EI kappa^2 / 2 at kappa_ref: k_b = 9 EI / (kappa_ref^2 l0^5) (docs/mechanics.md).
  const double k_bend = 9.0 * params_.bend_stiffness / (kappa_ref * kappa_ref * std::pow(l0, 5));
  // Bend springs also resist stretching (axial stiffness 4 k_b l0); the stretch springs take
  // the rest so that the chain's total axial stiffness stays EA. They never drop below half of
  // EA / l0: without them the chain has a zero-energy zig-zag (alternate points folding), which
  // the (i, i+2) springs cannot see.
  const double k_stretch =
      std::max(params_.stretch_stiffness / l0 - 4.0 * k_bend, 0.5 * params_.stretch_stiffness / l0);
  if (4.0 * k_bend * l0 > params_.stretch_stiffness) {
    warnings_.push_back(
        Cat("at ", n, " control points the bend springs alone give an axial stiffness of ",
            4.0 * k_bend * l0, " N, more than stretch_stiffness = ", params_.stretch_stiffness,
            " N: the tube is stiffer in stretch than asked. Use fewer control points, a larger "
            "bend_reference_curvature or a smaller bend_stiffness (docs/mechanics.md)"));
  }
  const double c = params_.spring_damping * segment_mass();
  for (int i = 0; i + 1 < n; ++i) stretch_springs_.push_back({i, i + 1, l0, k_stretch, c});
  if (k_bend > 0.0 || c > 0.0) {
    for (int i = 0; i + 2 < n; ++i) bend_springs_.push_back({i, i + 2, 2.0 * l0, k_bend, c});
  }
}

void Model::BuildPins() {
  const int p = static_cast<int>(params_.pinned.size());
  if (p == 0) return;
  MatX g = MatX::Zero(p, num_points());
  for (int r = 0; r < p; ++r) {
    Pin pin;
    pin.at = MakeCurvePoint(params_.pinned[r]);
    pin.position = Evaluate(pin.at, params_.initial_q);
    pins_.push_back(pin);
    for (int a = 0; a < 4; ++a) g(r, pin.at.first + a) += pin.at.w(a);
  }
  pin_y_ = g.transpose();
  for (int col = 0; col < p; ++col) {
    VecX column = pin_y_.col(col);
    mass_factor_.SolveInPlace(&column);
    pin_y_.col(col) = column;
  }
  const MatX schur = g * pin_y_;
  Eigen::FullPivLU<MatX> lu(schur);
  ThrowUnless(lu.isInvertible(), "intestine.pinned: two pins constrain the same curve point");
  pin_schur_inverse_ = lu.inverse();
}

const Eigen::Matrix4d& Model::NodeDerivatives(int segment) const {
  if (segment == 0) return node_dw_first_;
  if (segment == num_segments() - 1) return node_dw_last_;
  return node_dw_interior_;
}

CurvePoint Model::MakeCurvePoint(double s) const {
  const spline::SegmentBasis b = curve_.BasisAt(s);
  CurvePoint p;
  p.s = s;
  p.first = b.first;
  p.w = Eigen::Vector4d(b.w[0], b.w[1], b.w[2], b.w[3]);
  return p;
}

Vec3 Model::Evaluate(const CurvePoint& p, const Points& q) {
  return (q.middleRows<4>(p.first).transpose() * p.w);
}

}  // namespace viscera::mechanics
