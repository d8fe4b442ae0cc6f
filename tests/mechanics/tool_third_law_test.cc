// Newton's third law between the hand, the tool's tip and a free tube: a tool pushing a loop
// that nothing else holds (no gravity, no drag) moves it along at the hand's speed, and the
// impulse the hand gives equals the momentum the tube and the tip gain, at every speed the device
// allows and every rate a session runs. The control: the tip integrated in its own cycles against
// the tube held still (and the tube's solve holding the tool still) locks the contact at 100 Hz.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "mechanics/banded_cholesky.h"
#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {
namespace {

// A free tube along x at z = 0, and a tool whose shaft comes down from above and whose tip
// stands beside the tube's middle. Two of them: a 40 cm, 100 g tube of 32 points pushed by a
// slanted shaft, and a 30 cm, 80 g tube of 16 points with its self-contacts, pushed by a shaft
// that stands upright over the tube's side.
struct PushSetup {
  double length, mass;
  int points;
  bool self;
  Vec3 port;
};
const PushSetup kSlanted{0.4, 0.1, 32, false, Vec3(0.2, -0.05, 0.4)};
const PushSetup kUpright{0.3, 0.08, 16, true, Vec3(0.15, -0.03, 0.3)};

std::string Scene(const PushSetup& setup, double rate_hz) {
  char text[1000];
  std::snprintf(text, sizeof text, R"(
[simulation]
rate_hz = %g
integrator = "implicit"
gravity = [0.0, 0.0, 0.0]
[intestine]
length = %g
radius = 0.0125
mass = %g
control_points = %d
stretch_stiffness = 100.0
bend_stiffness = 1.0e-4
continuous_stretch = 0.2
damping = 0.0
spring_damping = 2.0
[intestine.shape]
kind = "straight"
start = [0.0, 0.0, 0.0]
direction = [1.0, 0.0, 0.0]
[contacts]
self = %s
[[tool]]
name = "pusher"
port = [%g, %g, %g]
radius = 0.0025
max_force = 5.0
)",
                rate_hz, setup.length, setup.mass, setup.points, setup.self ? "true" : "false",
                setup.port.x(), setup.port.y(), setup.port.z());
  return text;
}

struct Push {
  double tube_speed = 0.0;    // the pushed part's mean speed along the push, last half (m/s)
  double centre_speed = 0.0;  // the tube's centre of mass's, over the same time (m/s)
  double hand = 0.0;          // impulse the hand gave along the push (N s)
  double momentum = 0.0;      // the tube's and the tip's momentum along the push (N s)
  double tip_momentum = 0.0;  // the tip's alone (N s)
  double lever = 1.0;         // where the tube's middle touches the shaft: 0 port .. 1 tip
};

// Pushes the tube's middle along +y at `speed` for long enough to move it 4 cm. The tube is
// floppy: it drapes around the shaft, its ends trailing, so it is the pushed part that follows
// the hand, and the whole tube's centre of mass that carries the hand's impulse. With `below` >
// 0 the tip passes that far under the tube, so the shaft pushes it, nearer the port.
Push PushTube(const PushSetup& setup, double rate_hz, double speed, bool tips_in_solve,
              double below = 0.0) {
  ModelParams params = scene::ParseScene(Scene(setup, rate_hz)).model;
  params.contacts.tips_in_solve = tips_in_solve;
  const Model model(params);
  State state = InitialState(model);
  Workspace workspace(model);
  const double reach = params.radius + params.tools[0].radius;
  // 1 mm short of the tube's side where the shaft crosses the tube's height
  const double port_height = setup.port.z(), tube_y = 0.0 - reach - 0.001;
  const double slant = (tube_y - setup.port.y()) / port_height;  // shaft's y per metre down
  const Vec3 start(0.5 * setup.length, tube_y + slant * below, -below);
  const double duration = 0.04 / speed + 0.1;
  const int steps = static_cast<int>(std::lround(duration * rate_hz));
  const double dt = 1.0 / rate_hz;
  Points scratch(model.num_points(), 3);
  auto tube_momentum = [&] {
    BandMultiply(model.mass_band(), state.qd, &scratch);
    return scratch.col(1).sum();
  };
  auto tube_centre = [&] {
    BandMultiply(model.mass_band(), state.q, &scratch);
    return scratch.col(1).sum() / params.mass;
  };
  Push push;
  double centre_half = 0.0, middle_half = 0.0;
  for (int k = 0; k < steps; ++k) {
    ToolTarget target;
    target.tip = start + Vec3(0.0, speed * (k + 1) * dt, 0.0);
    target.jaw = 1.0;
    Step(model, {{}, std::span<const ToolTarget>(&target, 1)}, &state, &workspace);
    push.hand -= dt * state.tools[0].force.y();  // the hand feels the reaction of what it gives
    if (k + 1 == steps / 2)
      centre_half = tube_centre(), middle_half = model.curve().Position(state.q, 0.5).y();
  }
  const double half = (steps - steps / 2) * dt;
  push.tube_speed = (model.curve().Position(state.q, 0.5).y() - middle_half) / half;
  push.centre_speed = (tube_centre() - centre_half) / half;
  push.tip_momentum = params.tools[0].mass * state.tools[0].tip_velocity.y();
  push.momentum = tube_momentum() + push.tip_momentum;
  const Vec3 port = setup.port, tip = state.tools[0].tip,
             middle = model.curve().Position(state.q, 0.5);
  push.lever = (middle - port).dot(tip - port) / (tip - port).squaredNorm();
  EXPECT_TRUE(state.q.allFinite());
  return push;
}

TEST(ToolThirdLaw, AFreeTubeFollowsThePushAndTheHandsImpulseIsItsMomentum) {
  for (const PushSetup* tube : {&kSlanted, &kUpright}) {
    const PushSetup& setup = *tube;
    SCOPED_TRACE(setup.length);
    for (double rate : {100.0, 250.0, 1000.0}) {
      for (double speed : {0.01, 0.08, 0.2, 0.5}) {
        const Push p = PushTube(setup, rate, speed, true);
        std::printf(
            "%2.0f cm tube, %6.0f Hz %4.0f cm/s: pushed part %.4f m/s (%.3f of the hand's; centre "
            "of mass %.3f), hand impulse %.5f N s, momentum %.5f N s\n",
            100 * setup.length, rate, 100 * speed, p.tube_speed, p.tube_speed / speed,
            p.centre_speed / speed, p.hand, p.momentum);
        // At 1 cm/s the coarse tube's middle runs up to 20 % ahead of the upright shaft, off it
        // (its impulse is still the hand's): only the faster pushes hold it against the shaft.
        if (tube == &kSlanted || speed > 0.05) {
          EXPECT_NEAR(p.tube_speed, speed, 0.1 * speed)
              << rate << " Hz, " << speed << " m/s: the tube did not follow";
        }
        EXPECT_NEAR(p.hand, p.momentum, 0.1 * std::abs(p.momentum))
            << rate << " Hz, " << speed << " m/s";
      }
    }
  }
}

TEST(ToolThirdLaw, PushedByTheShaftThePortTakesItsShare) {
  // The shaft pivots at the port: a contact at lever l from the port moves at l times the tip's
  // speed and moves l of its force to the tip, the port (the abdominal wall) taking the rest.
  // So the hand's impulse is the tip's momentum and l of the tube's, not all of it.
  for (double rate : {100.0, 1000.0}) {
    for (double speed : {0.02, 0.08, 0.2}) {
      const Push p = PushTube(kSlanted, rate, speed, true, 0.2);
      const double tube = p.momentum - p.tip_momentum;
      std::printf(
          "shaft, %4.0f Hz %4.0f cm/s: lever %.3f, pushed part %.4f m/s (%.3f of the hand's), "
          "hand impulse %.5f N s, tip %.5f + lever x tube %.5f = %.5f N s (tube %.5f)\n",
          rate, 100 * speed, p.lever, p.tube_speed, p.tube_speed / speed, p.hand, p.tip_momentum,
          p.lever * tube, p.tip_momentum + p.lever * tube, tube);
      EXPECT_NEAR(p.tube_speed, p.lever * speed, 0.1 * p.lever * speed) << rate << " Hz, " << speed;
      EXPECT_NEAR(p.hand, p.tip_momentum + p.lever * tube, 0.05 * tube) << rate << " Hz, " << speed;
      EXPECT_LT(p.hand, p.momentum - 0.5 * (1.0 - p.lever) * tube) << "the port took no share";
    }
  }
}

// A 40 cm, 100 g tube draped by gravity (along -z) over a level shaft that crosses it at 3/4 of
// the way from the port to the tip; the tool then slides along its own axis (+x), ramping up to
// `speed` over 0.2 s and holding it for 0.3 s. The draped tube's weight presses it on the shaft,
// and static friction carries it along. The tube's weight sags the tip on its coupling; the hand
// lifts it back level before the slide, since the port's share of a force across a tilted shaft
// would also push along x.
struct Slide {
  double tube_speed = 0.0;       // the draped middle's speed along the shaft, last 0.1 s (m/s)
  double tip_speed = 0.0;        // the tip's, at the end (m/s)
  double hand = 0.0;             // impulse the hand gave along the shaft during the slide (N s)
  double tube = 0.0, tip = 0.0;  // momentum along the shaft they gained during it (N s)
};

Slide SlideAlongShaft(double rate_hz, double speed) {
  char text[1000];
  std::snprintf(text, sizeof text, R"(
[simulation]
rate_hz = %g
integrator = "implicit"
gravity = [0.0, 0.0, -9.81]
[intestine]
length = 0.4
mass = 0.1
control_points = 32
damping = 0.0
[intestine.shape]
kind = "straight"
start = [0.0, -0.2, 0.0152]
direction = [0.0, 1.0, 0.0]
[contacts]
tool_friction = 0.5
[[tool]]
name = "slider"
port = [-0.3, 0.0, 0.0]
radius = 0.0025
)",
                rate_hz);
  const Model model(scene::ParseScene(text).model);
  State state = InitialState(model);
  Workspace workspace(model);
  const double dt = 1.0 / rate_hz, drape = 1.0, ramp = 0.2, hold = 0.3;
  const int steps = static_cast<int>(std::lround((drape + ramp + hold) * rate_hz));
  Points scratch(model.num_points(), 3);
  auto tube_momentum = [&] {
    BandMultiply(model.mass_band(), state.qd, &scratch);
    return scratch.col(0).sum();
  };
  Slide slide;
  double travel = 0.0, lift = 0.0, middle_before = 0.0, tube_before = 0.0, tip_before = 0.0;
  const int level_at = static_cast<int>(std::lround(0.7 * drape * rate_hz));
  for (int k = 0; k < steps; ++k) {
    const double t = (k + 1) * dt - drape;
    if (t > 0.0) travel += dt * speed * std::min(1.0, t / ramp);
    if (k == level_at) lift = -state.tools[0].tip.z();
    if (t > 0.0 && t <= dt * 1.5) {
      tube_before = tube_momentum();
      tip_before = model.params().tools[0].mass * state.tools[0].tip_velocity.x();
    }
    ToolTarget target;
    target.tip = Vec3(0.1 + travel, 0.0, lift);
    target.jaw = 1.0;
    Step(model, {{}, std::span<const ToolTarget>(&target, 1)}, &state, &workspace);
    if (t > 0.0) slide.hand -= dt * state.tools[0].force.x();
    if (k + 1 == steps - static_cast<int>(std::lround(0.1 * rate_hz)))
      middle_before = model.curve().Position(state.q, 0.5).x();
  }
  EXPECT_TRUE(state.q.allFinite());
  EXPECT_GT(model.curve().Position(state.q, 0.5).z(), 0.0) << "the tube fell off the shaft";
  slide.tube_speed = (model.curve().Position(state.q, 0.5).x() - middle_before) / 0.1;
  slide.tip_speed = state.tools[0].tip_velocity.x();
  slide.tube = tube_momentum() - tube_before;
  slide.tip = model.params().tools[0].mass * slide.tip_speed - tip_before;
  return slide;
}

TEST(ToolThirdLaw, SlidAlongItsShaftTheToolCarriesTheTubeAndThePortHoldsNothing) {
  // The shaft slides through the port: a point of it moves along the shaft at the tip's speed
  // wherever it is, and the port holds no force along the shaft. So friction carries a stuck
  // tube at the tip's full speed, and the hand gives the whole impulse along the shaft (the
  // lever rule's share, l = 3/4 here, is for forces across it).
  for (double rate : {100.0, 1000.0}) {
    for (double speed : {0.02, 0.08}) {
      const Slide s = SlideAlongShaft(rate, speed);
      std::printf(
          "slide, %4.0f Hz %2.0f cm/s: tube %.4f m/s, tip %.4f m/s; hand impulse %.5f N s, tube "
          "%.5f + tip %.5f = %.5f N s\n",
          rate, 100 * speed, s.tube_speed, s.tip_speed, s.hand, s.tube, s.tip, s.tube + s.tip);
      EXPECT_NEAR(s.tube_speed, speed, 0.05 * speed) << rate << " Hz, " << speed;
      EXPECT_NEAR(s.hand, s.tube + s.tip, 0.05 * s.tube) << rate << " Hz, " << speed;
    }
  }
}

TEST(ToolThirdLaw, WithTheTipInItsOwnCyclesTheContactLocksAt100Hz) {
  // The control: the tube's solve holds the tool still and the tip's cycles hold the tube still.
  const Push p = PushTube(kSlanted, 100.0, 0.1, false);
  std::printf(
      "own cycles, 100 Hz 10 cm/s: pushed part %.4f m/s, hand impulse %.5f N s, momentum %.5f N "
      "s\n",
      p.tube_speed, p.hand, p.momentum);
  EXPECT_LT(p.tube_speed, 0.9 * 0.1) << "the pushed part followed";
  EXPECT_GT(std::abs(p.hand - p.momentum), 0.1 * std::abs(p.momentum))
      << "the hand's impulse matched";
}

}  // namespace
}  // namespace viscera::mechanics
