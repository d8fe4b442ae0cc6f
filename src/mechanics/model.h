#pragma once
/// The immutable, validated intestine model: geometry, masses, springs, pins, attachments and
/// the factorized mass matrix. Built once; shared read-only by any number of threads (the
/// MuJoCo mjModel habit). Everything a step writes lives in State and Workspace.
#include <string>
#include <vector>

#include "mechanics/banded_cholesky.h"
#include "mechanics/block_band.h"
#include "mechanics/model_params.h"
#include "spline/catmull_rom.h"

namespace viscera::mechanics {

/// A Provot spring between control points i and j (France et al. 2005, section 3.3).
struct Spring {
  int i = 0;
  int j = 0;
  double rest = 0.0;       ///< m
  double stiffness = 0.0;  ///< N/m
  double damping = 0.0;    ///< N s/m along the spring
};

/// A point of the curve, through its 4 basis weights, and where it is held.
struct CurvePoint {
  double s = 0.0;
  int first = 0;                                ///< first control point of its window
  Eigen::Vector4d w = Eigen::Vector4d::Zero();  ///< b_{first+a}(s)
};

struct Attachment {
  CurvePoint at;
  Vec3 anchor = Vec3::Zero();
  double stiffness = 0.0;
  double damping = 0.0;
  double rest_length = 0.0;
};

/// One tether of the mesentery: from `root` to the curve point, slack up to `length`.
struct Tether {
  CurvePoint at;
  Vec3 root = Vec3::Zero();  ///< m, world
  double length = 0.0;       ///< slack length (m)
  double stiffness = 0.0;    ///< N/m beyond the onset
  double damping = 0.0;      ///< N s/m along the tether, when taut
  double onset = 0.0;        ///< m of stretch over which the pull grows from 0 to stiffness
};

struct Pin {
  CurvePoint at;
  Vec3 position = Vec3::Zero();
};

class Model {
 public:
  /// @throws InputError naming the parameter, its value and the reason when params are invalid.
  explicit Model(ModelParams params);

  const ModelParams& params() const { return params_; }
  const spline::CatmullRom& curve() const { return curve_; }
  int num_points() const { return curve_.num_points(); }
  int num_segments() const { return curve_.num_segments(); }

  double step_size() const { return 1.0 / params_.rate_hz; }
  double substep_size() const { return step_size() / params_.substeps; }
  double rest_segment_length() const { return params_.length / num_segments(); }
  double segment_mass() const { return params_.mass / num_segments(); }

  const Band& mass_band() const { return mass_band_; }
  /// Each control point's share of the mass, m integral b_i ds (the rows of M summed): the
  /// control points are not material points, so these weigh their positions and velocities.
  const VecX& mass_shares() const { return mass_shares_; }
  /// The tube's linear momentum at velocities qd (N s): M qd summed over the points.
  Vec3 Momentum(const Points& qd) const { return qd.transpose() * mass_shares_; }
  /// The tube's centre of mass at q.
  Vec3 CentreOfMass(const Points& q) const {
    return (q.transpose() * mass_shares_) / mass_shares_.sum();
  }
  /// -dF/dqd of the viscous friction, gamma M on each axis: every sub-step's damping Jacobian
  /// starts from it.
  const BlockBand& viscous_damping() const { return viscous_damping_; }
  const BandedCholesky& mass_factor() const { return mass_factor_; }
  /// Generalized gravity force, constant: row i = (m integral b_i ds) g. #N by 3.
  const Points& gravity_force() const { return gravity_force_; }

  const std::vector<Spring>& stretch_springs() const { return stretch_springs_; }
  const std::vector<Spring>& bend_springs() const { return bend_springs_; }
  const std::vector<Attachment>& attachments() const { return attachments_; }
  const std::vector<Pin>& pins() const { return pins_; }
  /// The mesentery's tethers (empty without [mesentery]), in increasing s.
  const std::vector<Tether>& tethers() const { return tethers_; }

  /// d b_{first+a} / du at the 4 Gauss-Legendre nodes of segment j: row = node, column = a.
  const Eigen::Matrix4d& NodeDerivatives(int segment) const;

  /// Pin projection: Y = M^-1 G^T (#N by #pins) and (G M^-1 G^T)^-1 (#pins square), G being the
  /// pins' basis rows.
  const MatX& pin_y() const { return pin_y_; }
  const MatX& pin_schur_inverse() const { return pin_schur_inverse_; }

  /// What the user should know about how the parameters were realized (e.g. a resolution at
  /// which the bend springs alone exceed the axial stiffness asked for).
  const std::vector<std::string>& warnings() const { return warnings_; }

  /// Evaluates a curve point from its weights.
  static Vec3 Evaluate(const CurvePoint& p, const Points& q);
  CurvePoint MakeCurvePoint(double s) const;

 private:
  void BuildSprings();
  void BuildPins();
  void BuildTethers();

  ModelParams params_;
  spline::CatmullRom curve_;
  Band mass_band_;
  VecX mass_shares_;
  BlockBand viscous_damping_;
  BandedCholesky mass_factor_;
  Points gravity_force_;
  std::vector<Spring> stretch_springs_, bend_springs_;
  std::vector<Attachment> attachments_;
  std::vector<Pin> pins_;
  std::vector<Tether> tethers_;
  Eigen::Matrix4d node_dw_first_, node_dw_interior_, node_dw_last_;
  MatX pin_y_, pin_schur_inverse_;
  std::vector<std::string> warnings_;
};

}  // namespace viscera::mechanics
