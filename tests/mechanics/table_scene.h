#pragma once
// A 60 cm tube lying on a table, its ends held, and one grasper above its middle: the tools'
// tests and the assessment's scripted pulls drive it.
namespace viscera::testing {

inline constexpr const char* kTableScene = R"(
[simulation]
rate_hz = 200
integrator = "implicit"
[intestine]
length = 0.6
radius = 0.0125
mass = 0.15
control_points = 40
stretch_stiffness = 100.0
bend_stiffness = 1.0e-4
continuous_stretch = 0.2
damping = 2.0
spring_damping = 2.0
[intestine.shape]
kind = "straight"
start = [0.0, 0.0, 0.0125]
direction = [1.0, 0.0, 0.0]
[contacts]
self = false
stiffness = 500.0
damping = 1.0
[[obstacle]]
kind = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]
[[attachment]]
at = 0.0
stiffness = 50.0
[[attachment]]
at = 1.0
stiffness = 50.0
[[tool]]
name = "grasper"
port = [0.3, -0.15, 0.3]
radius = 0.0025
max_force = 5.0
)";

}  // namespace viscera::testing
