#pragma once
// Small scenes for session tests: fast to step, no network.
#include <memory>
#include <string>

#include "mechanics/model.h"
#include "scene/scene.h"

namespace viscera::session::testing {

/// A 0.5 m, 21-point tube held at both ends, implicit Euler at `rate_hz`.
inline std::string SmallSceneToml(double rate_hz = 100.0) {
  return "[simulation]\nrate_hz = " + std::to_string(rate_hz) +
         "\nsubsteps = 1\nintegrator = \"implicit\"\ngravity = [0.0, 0.0, -9.81]\n"
         "[intestine]\nlength = 0.5\nradius = 0.0125\nmass = 0.12\ncontrol_points = 21\n"
         "stretch_stiffness = 100.0\nbend_stiffness = 1.0e-4\ncontinuous_stretch = 0.5\n"
         "damping = 1.0\nspring_damping = 2.0\npinned = [\"start\", \"end\"]\n"
         "[intestine.shape]\nkind = \"straight\"\nstart = [-0.2, 0.0, 0.1]\ndirection = [1.0, 0.0, "
         "0.0]\n";
}

/// The small scene with one tool, as a scene file declares it ([[tool]]), so that a record
/// of it replays with its tool: idle 0.2 s after the last pose.
inline std::string ToolSceneToml() {
  return SmallSceneToml() +
         "[[tool]]\nname = \"grasper\"\nport = [0.05, 0.0, 0.4]\nidle_timeout = 0.2\n";
}

/// A scene whose step costs several milliseconds (RK4, 200 sub-steps of a 101-point tube)
/// at 1 kHz: no machine keeps its 1 ms deadlines.
inline std::string OverloadedSceneToml() {
  return "[simulation]\nrate_hz = 1000\nsubsteps = 200\nintegrator = \"rk4\"\n"
         "gravity = [0.0, 0.0, -9.81]\n"
         "[intestine]\nlength = 0.5\nradius = 0.0125\nmass = 0.12\ncontrol_points = 101\n"
         "stretch_stiffness = 10.0\nbend_stiffness = 1.0e-4\npinned = [\"start\", \"end\"]\n"
         "[intestine.shape]\nkind = \"straight\"\nstart = [-0.2, 0.0, 0.1]\ndirection = [1.0, 0.0, "
         "0.0]\n";
}

/// A scene whose explicit integrator is far beyond its stability limit: it blows up within
/// a few steps (RK4, one sub-step, stiff springs).
inline std::string UnstableSceneToml() {
  return "[simulation]\nrate_hz = 100\nsubsteps = 1\nintegrator = \"rk4\"\n"
         "[intestine]\nlength = 0.5\nradius = 0.0125\nmass = 0.12\ncontrol_points = 41\n"
         "stretch_stiffness = 1.0e4\nbend_stiffness = 1.0e-4\n"
         "[intestine.shape]\nkind = \"serpentine\"\nstart = [0.0, 0.0, 0.1]\n"
         "amplitude = 0.05\nwavelength = 0.2\n";
}

/// A 0.5 m tube coiled tighter than its diameter (its turns press on each other from the start:
/// self pairs in every implicit solve), falling under `gravity_z` (m/s²) onto a floor.
inline std::string CoiledSceneToml(double gravity_z = -9.81) {
  return "[simulation]\nrate_hz = 100\nintegrator = \"implicit\"\ngravity = [0.0, 0.0, " +
         std::to_string(gravity_z) +
         "]\n[intestine]\nlength = 0.5\nradius = 0.0125\nmass = 0.125\ncontrol_points = 40\n"
         "stretch_stiffness = 100.0\nbend_stiffness = 1.0e-4\ncontinuous_stretch = 0.5\n"
         "damping = 0.5\nspring_damping = 2.0\n"
         "[intestine.shape]\nkind = \"helix\"\ncenter = [0.0, 0.0, 0.05]\naxis = [0.0, 0.0, 1.0]\n"
         "radius = 0.03\npitch = 0.02\n"
         "[[obstacle]]\nkind = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n";
}

/// The coiled scene with its conjugate gradients capped at one iteration ([simulation]
/// cg_iteration_cap): a solve with self pairs falls short of its tolerance, is halved to the
/// deepest and accepted short, and counted (State::unconverged_solves). With a gravity of
/// -1e6 m/s² every step also runs away (a blow-up).
inline std::string UnconvergedSceneToml(double gravity_z = -9.81) {
  std::string toml = CoiledSceneToml(gravity_z);
  const std::string simulation = "[simulation]\n";
  toml.insert(simulation.size(), "cg_iteration_cap = 1\n");
  return toml;
}

inline std::shared_ptr<const mechanics::Model> UnconvergedModel(double gravity_z = -9.81) {
  return std::make_shared<const mechanics::Model>(
      scene::ParseScene(UnconvergedSceneToml(gravity_z), "coiled").model);
}

/// The small scene's model with `num_tools` tools (added in code: the [[tool]] scene key
/// belongs to the mechanics work), each idle after `idle_timeout` s.
inline std::shared_ptr<const mechanics::Model> SmallModel(int num_tools, double rate_hz = 100.0,
                                                          double idle_timeout = 0.25) {
  scene::Scene scene = scene::ParseScene(SmallSceneToml(rate_hz), "small");
  for (int i = 0; i < num_tools; ++i) {
    mechanics::ToolParams tool;
    tool.name = "grasper" + std::to_string(i);
    tool.port = Vec3(0.0, 0.1 * i, 0.3);
    tool.idle_timeout = idle_timeout;
    scene.model.tools.push_back(tool);
  }
  return std::make_shared<const mechanics::Model>(std::move(scene.model));
}

}  // namespace viscera::session::testing
