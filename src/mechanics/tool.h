#pragma once
/// Laparoscopic tools (France et al. 2005, Figure 4b): a shaft capsule from the
/// trocar port to the tip, jaws at the tip. The device (a client) sets a target pose; the
/// simulated tool follows it through a virtual coupling (spring-damper), so it cannot tunnel
/// through tissue, and the coupling force is the force feedback.
#include <cstdint>
#include <string>

#include <Eigen/Geometry>

#include "common/types.h"

namespace viscera::mechanics {

/// A tool of the scene ([[tool]]), immutable.
struct ToolParams {
  std::string name;
  double radius = 0.0025;             ///< shaft and jaw radius (m)
  double length = 0.35;               ///< shaft length (m), for rendering and reach checks
  Vec3 port = Vec3::Zero();           ///< trocar point the shaft passes through (m)
  double max_force = 5.0;             ///< device-safe force clamp (N)
  double coupling_stiffness = 300.0;  ///< virtual coupling (N/m)
  double coupling_damping = 4.0;      ///< virtual coupling (N s/m)
  double mass = 0.05;                 ///< simulated tool tip mass (kg); its weight is not felt
  double grasp_stiffness = 500.0;     ///< jaw-to-tube spring while grasping (N/m)
  double grasp_reach = 0.0;  ///< how far from the jaws a tube can be grasped (m); 0 = 2 radii
  /// Grip of fully closed jaws (N): the jaws grip with jaw_force (0.3 - jaw) / 0.3 once closed
  /// below 0.3. 0: no grip model, the grasp holds whatever pulls it.
  double jaw_force = 0.0;
  /// Friction of a jaw face on the serosa: the grasp holds 2 jaw_friction grip (two faces) and
  /// slips beyond it.
  double jaw_friction = 0.1;
  double idle_timeout = 0.25;  ///< s without a target before the tool goes idle (server side)
};

/// What the device asks for, one per tool, each step.
struct ToolTarget {
  Vec3 tip = Vec3::Zero();                                          ///< target tip position (m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< jaw frame
  double jaw = 1.0;  ///< jaw opening, 0 = closed .. 1 = open
  /// false when the device is idle (no recent pose): the coupling force fades to zero and the
  /// jaws open.
  bool active = true;
};

/// The simulated tool and its haptic output after a step.
struct ToolState {
  bool initialized = false;  ///< false until the first target: the tip then starts there
  ToolTarget target;         ///< the latest target (held when a step brings none)
  /// The target's tip at the start of this step: the coupling follows the target from there to
  /// `target.tip` across the step, as a device's hand moved, not in one jump at its start.
  Vec3 target_from = Vec3::Zero();
  Vec3 tip = Vec3::Zero();           ///< simulated tip position (m)
  Vec3 tip_velocity = Vec3::Zero();  ///< m/s
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  double jaw = 1.0;
  bool grasping = false;
  double grasp_s = 0.0;  ///< curve parameter held while grasping
  /// The grasp spring's rest offset from the held point to the jaws: the jaws' offset when they
  /// closed, shrinking as the tube is drawn in (m).
  Vec3 grasp_offset = Vec3::Zero();
  double grasp_scale = 0.0;  ///< the grasp spring's share: 1 held, fading to 0 after a release
  /// The sphere nearest to the jaws when they grasped (-1: none): it and its neighbours are
  /// between the jaws, no contact of the shaft, until they are out of it after a release.
  int held_sphere = -1;
  double grasp_time = 0.0;  ///< s since the grasp engaged
  double grasp_jaw = 1.0;   ///< the narrowest jaw opening of this grasp: opening past it releases
  double grip_force = 0.0;  ///< the jaws' grip on the held tube (N; 0 without a grasp or jaw_force)
  /// The tube slipped out of the jaws and they are still closed: no grasp until they open.
  bool slipped = false;
  int64_t slips = 0;  ///< times the tube slipped out of these jaws (the pull beat the hold)
  /// The grasp spring's pull on the held tube (N; 0 without a grasp): the traction the jaws put
  /// on the bowel, without the shaft's and jaws' contacts pressing on it.
  double grasp_pull = 0.0;
  double coupling_scale = 1.0;  ///< 1 while active, fades to 0 when idle
  /// Force on the user's hand (N): pressing down into tissue gives an upward force. Clamped.
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();     ///< about the port (N m)
  Mat3 stiffness = Mat3::Zero();  ///< local dF/dx (N/m) for haptic interpolation between steps
  bool clamped = false;           ///< force was limited to max_force this step
  /// Force the tool puts on the intestine (N): its contacts with the tube and its grasp spring,
  /// as the last sub-step applied them (the assessment's tissue force; zero while idle).
  Vec3 tissue_force = Vec3::Zero();
};

}  // namespace viscera::mechanics
