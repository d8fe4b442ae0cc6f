#pragma once
/// Plain, unvalidated description of an intestine model, in SI units. Model's constructor
/// validates it. Scenes (src/scene) fill it from TOML.
#include <optional>
#include <utility>
#include <vector>

#include "collision/obstacle.h"
#include "common/types.h"
#include "mechanics/scope_params.h"
#include "mechanics/task_params.h"
#include "mechanics/tool.h"

namespace viscera::mechanics {

enum class IntegratorKind { kRk4, kImplicitEuler };
/// The implicit integrator's scheme: BDF2 (second order; backward Euler where it cannot build on
/// the last sub-step) or backward Euler alone (first order, the more damped).
enum class ImplicitScheme { kBdf2, kBackwardEuler };
enum class MassSolverKind { kBanded, kCholmod };
/// How the implicit integrator solves M + h D + h^2 K: 3x3 block-band Cholesky (valid while the
/// pattern is the chain's band) or CHOLMOD (any pattern). docs/benchmarks.md compares them.
enum class LinearSolverKind { kBlockBand, kCholmod };
/// The Terzopoulos stretching energy over the whole curve (the paper) or per segment.
enum class ContinuousScope { kGlobal, kSegment };

/// A soft spring from a curve point to a fixed world point (anatomical attachment, mesentery).
struct AttachmentParams {
  double s = 0.0;             ///< curve parameter in [0, 1]
  std::optional<Vec3> point;  ///< world anchor (m); default: where the curve point starts
  double stiffness = 0.0;     ///< N/m
  double damping = 0.0;       ///< N s/m, on the curve point's velocity
  double rest_length = 0.0;   ///< m; 0 = zero-length spring
};

/// The mesentery ([mesentery]): a fan of one-sided tethers from a root line on the posterior wall
/// to the whole intestine. The tether of curve parameter s runs from the root point
/// root_start + s (root_end - root_start) to P(s); it is slack up to its length L(s) and pulls
/// beyond (docs/mechanics.md, "Mesentery").
struct MesenteryParams {
  Vec3 root_start = Vec3::Zero();  ///< root's end at the duodenojejunal flexure (s = 0), m
  Vec3 root_end = Vec3::Zero();    ///< root's end at the ileocecal junction (s = 1), m
  /// Slack length profile: (s, L) pairs, s strictly increasing from 0 to 1, L > 0 (m);
  /// L(s) is interpolated linearly between them.
  std::vector<std::pair<double, double>> lengths;
  double stiffness = 0.0;  ///< N/m per metre of tube (a tether gets it times its share of tube)
  double damping = 0.0;    ///< N s/m per metre of tube, along a taut tether
  double onset =
      0.01;         ///< m: stretch d where the J-shaped pull k e^3 / (3 d^2) reaches stiffness k
  int tethers = 0;  ///< tethers at equal steps of s; 0: one per control point
  /// m added to every tether's length: a scene's settling starts with the tethers loose enough
  /// for its starting pose and tightens them gradually (scene::Settle). 0 in a running scene.
  double extra_slack = 0.0;
};

enum class FrictionLaw { kStickSlip, kRegularized };

/// Penalty contacts of the sphere chain ([contacts]; France et al. 2005, section 3.5).
struct ContactParams {
  bool self = false;         ///< self-contacts (scenes default to true)
  double stiffness = 500.0;  ///< N/m per unit penetration
  double damping = 1.0;      ///< N s/m along the normal
  /// Coulomb coefficients (docs/mechanics.md, "Tissue card"): the tube against the environment
  /// (wet serosa on peritoneum), against itself (serosa on serosa) and against a tool's steel.
  double friction = 0.05;
  double self_friction = 0.05;
  double tool_friction = 0.1;
  /// Implicit integrator with impact constraints: Coulomb's law with a static phase (kStickSlip,
  /// the default: a tangential spring to where the contact stuck, capped by the cone;
  /// docs/friction.md), or the regularized law, viscous below kFrictionSlip (kRegularized; RK4
  /// and the limiter alone always use it).
  FrictionLaw friction_law = FrictionLaw::kStickSlip;
  /// N/m: the stuck contact's tangential spring; 0: a fifth of the normal stiffness.
  double tangential_stiffness = 0.0;
  double margin =
      -1.0;  ///< m: pairs this close are candidates and count as contacts; < 0: radius / 4
  /// Implicit integrator: self pairs coupled exactly (true) or only through each side's own
  /// window (false: cheaper, but a pair moving together is dragged; docs/self-coupling.md).
  bool exact_pairs = true;
  /// Fraction of the radius: a contact that would end a sub-step deeper than this at its current
  /// speed is stopped there by an inelastic impulse (ImpactLimiter); 0 turns that off.
  double impact_depth = 0.05;
  /// Implicit integrator: impulses inside the implicit solve (through its system matrix) stop the
  /// impacts that the step's own forces would still drive deeper than impact_depth, and push any
  /// pair back within impact_depth + (10 % - impact_depth) / 4 of the radius by a position
  /// correction (docs/impacts.md).
  bool impact_constraints = true;
  /// The contact spheres stay where they were first placed along the tube (material points)
  /// instead of being re-placed along its arc length at every sub-step, which slides them into
  /// each other while an impact stretches the tube (docs/impacts.md).
  bool spheres_follow_material = true;
  /// Implicit integrator: each tool's tip is an unknown of the tube's solve, with its coupling and
  /// every tip-tube contact (docs/tool-coupling.md); false runs the tip in its own
  /// cycles against the tube held still (not action-reaction; kept to compare against).
  bool tips_in_solve = true;
};

/// Below this tangential speed friction is viscous (m/s): no stick-slip chatter at 100 Hz.
inline constexpr double kFrictionSlip = 0.01;

/// The intestine's defaults: the human small intestine's measured values (docs/mechanics.md,
/// "Tissue card", has the ranges and their sources). A scene's [intestine] that leaves a key out
/// gets these, not a tube without stiffness.
struct TissueCard {
  static constexpr double kRadius = 0.0125;           ///< m: 2.5 cm across (2.5-3 cm measured)
  static constexpr double kLinearDensity = 0.25;      ///< kg/m with contents (0.15-0.33 measured)
  static constexpr double kStretchStiffness = 100.0;  ///< EA (N): 48 at low strain, 350 at high
  static constexpr double kBendStiffness = 1.0e-4;  ///< EI (N m^2): 1.6e-5 collapsed, 3e-3 inflated
};

struct ModelParams {
  // [simulation]
  double rate_hz = 100.0;  ///< steps per simulated second
  int substeps = 1;        ///< integrator sub-steps per step
  IntegratorKind integrator = IntegratorKind::kRk4;
  MassSolverKind mass_solver = MassSolverKind::kBanded;
  LinearSolverKind linear_solver = LinearSolverKind::kBlockBand;
  /// Implicit integrator: a sub-step that turns a segment so far that its linearization misses
  /// more than LinearizationGuard::kMaxUnseenStretch of its length is done again as two
  /// halves (docs/integrators.md, "One linearization per sub-step").
  bool linearization_guard = true;
  /// Implicit integrator: BDF2 damps a free swing of frequency ω by O(h³ ω⁴), backward Euler by
  /// h ω² / 2 (docs/integrators.md, "Numerical damping: why BDF2").
  ImplicitScheme implicit_scheme = ImplicitScheme::kBdf2;
  /// Implicit integrator: the most conjugate-gradient iterations a linear solve may take before
  /// it counts as not converged; 0: ImplicitEulerIntegrator::kMaxCgIterationsExtended (240).
  /// Lowered only to drive solves down their unconverged path (the halvings, then a solve
  /// accepted short and counted in State::unconverged_solves): tests, diagnosis.
  int cg_iteration_cap = 0;
  Vec3 gravity{0.0, 0.0, -9.81};  ///< m/s^2

  // [intestine]
  double length = 0.0;             ///< rest length L (m); the rest shape is straight
  double radius = 0.0;             ///< tube radius (m)
  double mass = 0.0;               ///< total mass (kg)
  double stretch_stiffness = 0.0;  ///< axial stiffness EA (N)
  double bend_stiffness = 0.0;     ///< bending stiffness EI (N m^2)
  /// Curvature (1/m) at which the Provot bend springs' energy equals the rod's
  /// (docs/mechanics.md); <= 0 means 1 / radius.
  double bend_reference_curvature = 0.0;
  double continuous_stretch = 0.0;  ///< k of the Terzopoulos energy (J)
  ContinuousScope continuous_scope = ContinuousScope::kGlobal;
  double damping = 0.0;         ///< viscous friction (1/s): force density -damping * rho * dP/dt
  double spring_damping = 0.0;  ///< along each spring (1/s), times the segment mass
  std::vector<double> pinned;   ///< curve parameters held where they start
  std::vector<AttachmentParams> attachments;
  std::optional<MesenteryParams> mesentery;

  ContactParams contacts;
  std::vector<collision::Obstacle> obstacles;

  /// [[tool]]: laparoscopic tools, in this order in StepInputs::tools and State::tools.
  std::vector<ToolParams> tools;

  /// [[target]] and [assessment]: the training task (not read by the mechanics).
  TaskParams task;

  /// [camera]: the laparoscope through its port; none: a plain camera framing the intestine.
  std::optional<ScopeParams> scope;

  /// Starting control points (#N by 3, N >= 4).
  Points initial_q;
};

}  // namespace viscera::mechanics
