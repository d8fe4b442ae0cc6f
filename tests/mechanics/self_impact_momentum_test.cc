// A hard self-impact without external forces: a hairpin (two parallel arms joined by a half
// turn) laid out longer than its rest length, no gravity, no tools, no drag of the fluid, so its
// stretch springs snap the half turn shut and the arms hit each other. Nothing outside the tube
// acts on it, so its momentum (the mass matrix's: sum over the points of M q̇) must stay what it
// was (zero), and its energy may only fall (contacts and spring damping dissipate).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "mechanics/banded_cholesky.h"
#include "mechanics/implicit_euler.h"
#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Hairpin {
  double arm = 0.3;      // m: each straight arm's length, as laid out
  double gap = 0.06;     // m: between the arms' centre lines (the half turn's diameter)
  double stretch = 1.5;  // laid-out length over rest length
  double rate_hz = 100.0;
  double spacing = 0.016;  // m: between control points, as laid out
  double seconds = 0.6;
  std::string contacts;       // extra [contacts] keys
  std::string simulation;     // extra [simulation] keys
  bool momentum_kept = true;  // ImplicitEulerIntegrator::set_impact_momentum_kept
  bool stretch_redo = true;   // ImplicitEulerIntegrator::set_stretch_redo
};

// The control points of the laid-out hairpin: arm one along +x at y = +gap/2, the half turn
// about the origin on the -x side, arm two back along +x at y = -gap/2; equally spaced.
std::vector<Vec3> Layout(const Hairpin& h, double* length) {
  const double r = 0.5 * h.gap;
  const double turn = kPi * r;
  *length = 2.0 * h.arm + turn;
  const int n = std::max(8, static_cast<int>(std::lround(*length / h.spacing)) + 1);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) {
    const double s = *length * i / (n - 1);
    if (s <= h.arm) {
      points.emplace_back(h.arm - s, r, 0.0);
    } else if (s <= h.arm + turn) {
      const double angle = kPi / 2 + (s - h.arm) / r;  // from +y round -x to -y
      points.emplace_back(r * std::cos(angle), r * std::sin(angle), 0.0);
    } else {
      points.emplace_back(s - h.arm - turn, -r, 0.0);
    }
  }
  return points;
}

ModelParams HairpinParams(const Hairpin& h) {
  double laid = 0.0;
  const std::vector<Vec3> points = Layout(h, &laid);
  std::string list;
  for (const Vec3& p : points) {
    list += (list.empty() ? "[" : ", [") + std::to_string(p.x()) + ", " + std::to_string(p.y()) +
            ", " + std::to_string(p.z()) + "]";
  }
  // scenes/fall.toml's tube and contact law, without the fluid's drag (an external force)
  const std::string toml =
      "[simulation]\nrate_hz = " + std::to_string(h.rate_hz) +
      "\nintegrator = \"implicit\"\ngravity = [0.0, 0.0, 0.0]\n" + h.simulation +
      "[intestine]\nlength = " + std::to_string(laid / h.stretch) +
      "\nradius = 0.0125\nmass = " + std::to_string(0.25 * laid / h.stretch) +
      "\nstretch_stiffness = 100.0\nbend_stiffness = 1.0e-4\ncontinuous_stretch = 2.0\n"
      "damping = 0.0\nspring_damping = 2.0\n"
      "[intestine.shape]\nkind = \"points\"\npoints = [" +
      list +
      "]\n"
      "[contacts]\n" +
      h.contacts;  // self contacts: a scene's default
  return scene::ParseScene(toml, "hairpin").model;
}

struct ImpactRun {
  double arm_peak = 0.0;        // N s: the largest momentum of one arm (the +y half) in any step
  double momentum_error = 0.0;  // N s: the largest |total momentum| after any step (it starts at 0)
  double start_energy = 0.0;    // J
  double largest_gain = -INFINITY;  // J: the largest energy gain of one step
  int gain_step = -1;
  double deepest = 0.0;  // fraction of R: the deepest self pair after any step
  int max_self = 0;      // self pairs in contact, most in any step
  int worst_step = -1;   // where momentum_error was reached
  int64_t unconverged = 0;
  int max_substeps = 0;
};

ImpactRun Simulate(const Hairpin& h, bool verbose = false) {
  const ModelParams params = HairpinParams(h);
  const Model model(params);
  State state = InitialState(model);
  Workspace workspace(model);
  auto& integrator = dynamic_cast<ImplicitEulerIntegrator&>(workspace.integrator());
  integrator.set_impact_momentum_kept(h.momentum_kept);
  integrator.set_stretch_redo(h.stretch_redo);
  Interactions* in = workspace.interactions();
  Points mqd(model.num_points(), 3);
  ImpactRun run;
  run.start_energy = ComputeEnergies(model, state.q, state.qd, in).total();
  double previous = run.start_energy;
  const int steps = static_cast<int>(std::lround(h.seconds * h.rate_hz));
  for (int k = 0; k < steps; ++k) {
    Step(model, {}, &state, &workspace);
    BandMultiply(model.mass_band(), state.qd, &mqd);
    Vec3 total = Vec3::Zero(), arm = Vec3::Zero();
    for (int i = 0; i < model.num_points(); ++i) {
      total += mqd.row(i).transpose();
      if (state.q(i, 1) > 0.0) arm += mqd.row(i).transpose();
    }
    run.arm_peak = std::max(run.arm_peak, arm.norm());
    if (total.norm() > run.momentum_error) {
      run.momentum_error = total.norm();
      run.worst_step = k;
    }
    const Energies terms = ComputeEnergies(model, state.q, state.qd, in);
    const double e = terms.total();
    if (verbose) {
      std::printf(
          "  step %3d: momentum %+.3e %+.3e %+.3e N s, arm %.3e N s, energy %.6e J (%+.2e: kinetic "
          "%.4e, "
          "stretch %.4e, bend %.2e, continuous %.4e, contact %.3e), self %d, clearance %+.3f R, "
          "substeps %d\n",
          k, total.x(), total.y(), total.z(), arm.norm(), e, e - previous, terms.kinetic,
          terms.stretch, terms.bend, terms.continuous, terms.contact, state.contacts.self,
          std::isnan(state.contacts.min_clearance) ? 0.0
                                                   : state.contacts.min_clearance / params.radius,
          state.substeps);
    }
    if (e - previous > run.largest_gain) {
      run.largest_gain = e - previous;
      run.gain_step = k;
    }
    previous = e;
    if (!std::isnan(state.contacts.min_clearance)) {
      run.deepest = std::max(run.deepest, -state.contacts.min_clearance / params.radius);
    }
    run.max_self = std::max(run.max_self, state.contacts.self);
    run.max_substeps = std::max(run.max_substeps, state.substeps);
  }
  run.unconverged = state.unconverged_solves;
  EXPECT_TRUE(state.q.allFinite());
  return run;
}

std::string Describe(const Hairpin& h, const ImpactRun& r) {
  char line[512];
  std::snprintf(line, sizeof line,
                "%5.0f Hz arm %.2f m gap %.3f m stretch %.2f: momentum error %.3e N s (%.2f %% of "
                "an arm's %.3e N s, "
                "step %d); largest gain %+.3e J (%+.2e of %.4f J, step %d); deepest %.1f %% R, "
                "self pairs %d, "
                "unconverged %lld, max substeps %d",
                h.rate_hz, h.arm, h.gap, h.stretch, r.momentum_error,
                100.0 * r.momentum_error / r.arm_peak, r.arm_peak, r.worst_step, r.largest_gain,
                r.largest_gain / r.start_energy, r.start_energy, r.gain_step, 100.0 * r.deepest,
                r.max_self, static_cast<long long>(r.unconverged), r.max_substeps);
  return line;
}

// Two hairpins laid out at 1.8 and 2 times their rest length (17.7 and 37 J of spring energy):
// the half turn snaps shut within a few hundredths of a second, the arms hit each other and are
// held by the impact constraints (the pairs reach 4-6 % of R, 8-24 of them in contact).
std::vector<Hairpin> HardImpacts() {
  Hairpin wide;
  wide.arm = 0.25, wide.gap = 0.08, wide.stretch = 2.0;
  Hairpin shorter;
  shorter.arm = 0.2, shorter.gap = 0.08, shorter.stretch = 1.8;
  return {wide, shorter};
}

constexpr double kRoundOff =
    1e-9;  // of the energy at release (tests/mechanics/drop_energy_test.cc)

// The goal: the momentum stays within 1 % of one arm's (measured: 0.01-0.09 %, what the solve's
// CG leaves) and no step gains energy, at 100, 250 and 1000 Hz.
TEST(SelfImpactMomentum, AHairpinSnappingShutKeepsItsMomentumAndGainsNoEnergy) {
  for (Hairpin h : HardImpacts()) {
    for (double rate : {100.0, 250.0, 1000.0}) {
      h.rate_hz = rate;
      const ImpactRun r = Simulate(h);
      // the impact is there: the arms hit hard enough for the impact constraints to hold them
      // (at 100 Hz the snap's sub-steps are backward Euler, whose damping softens it to 1.4 %)
      EXPECT_GE(r.max_self, 5) << Describe(h, r);
      EXPECT_GT(r.deepest, 0.01) << Describe(h, r);
      EXPECT_GT(r.arm_peak, 0.03) << Describe(h, r);
      EXPECT_LT(r.momentum_error, 0.01 * r.arm_peak) << Describe(h, r);
      EXPECT_LE(r.largest_gain, kRoundOff * r.start_energy) << Describe(h, r);
    }
  }
}

// The measurement itself: the same hairpins without self contacts keep their momentum to
// round-off (the springs' forces are equal and opposite, and so is the implicit step's
// response), so what the test above allows is the contacts'.
TEST(SelfImpactMomentum, WithoutContactsTheMomentumIsKeptToRoundOff) {
  for (Hairpin h : HardImpacts()) {
    h.contacts = "self = false\n";
    for (double rate : {100.0, 1000.0}) {
      h.rate_hz = rate;
      const ImpactRun r = Simulate(h);
      EXPECT_LT(r.momentum_error, 1e-9 * r.arm_peak) << Describe(h, r);
    }
  }
}

// Free motion gains no energy either: without contacts, stretched hairpins snap straight and
// ring, stepped by BDF2 wherever its linearization saw the motion and by backward Euler where it
// did not. The control: BDF2 everywhere gains at 500 Hz and 1 kHz (0.9 % and 0.2 % of the energy
// in one step).
TEST(SelfImpactMomentum, WithoutContactsASnapGainsNoEnergyAtAnyRate) {
  double control_gain = 0.0;
  for (const auto& [arm, stretch] : {std::pair{0.3, 1.1}, {0.4, 1.05}, {0.2, 1.2}}) {
    Hairpin h;
    h.arm = arm, h.gap = 0.035, h.stretch = stretch;
    h.contacts = "self = false\n";
    for (double rate : {100.0, 250.0, 500.0, 1000.0}) {
      h.rate_hz = rate;
      h.stretch_redo = true;
      const ImpactRun r = Simulate(h);
      EXPECT_LE(r.largest_gain, kRoundOff * r.start_energy) << Describe(h, r);
      h.stretch_redo = false;
      const ImpactRun off = Simulate(h);
      control_gain = std::max(control_gain, off.largest_gain / off.start_energy);
    }
  }
  EXPECT_GT(control_gain, 1e-3) << "BDF2 everywhere gained no energy";
}

// The safeguard, switched off: the impulses and depth corrections held inside the solve act
// through the band system, where each side of a self pair is tied to the world by twice the
// pair's stiffness; an impact between the arms then creates momentum: 0.8-7 % of an arm's at
// 100 / 250 / 1000 Hz (7-26 % under the regularized friction law), more than the 1 % the goal
// above allows.
TEST(SelfImpactMomentum, ImpulsesThroughTheBandSystemAloneCreateMomentum) {
  double worst = 0.0;
  for (Hairpin h : HardImpacts()) {
    h.momentum_kept = false;
    for (double rate : {100.0, 250.0, 1000.0}) {
      h.rate_hz = rate;
      const ImpactRun stick_slip = Simulate(h);
      worst = std::max(worst, stick_slip.momentum_error / stick_slip.arm_peak);
      Hairpin regularized = h;
      regularized.contacts = "friction_law = \"regularized\"\n";
      const ImpactRun r = Simulate(regularized);
      EXPECT_GT(r.momentum_error, 0.05 * r.arm_peak) << Describe(regularized, r);
    }
  }
  EXPECT_GT(worst, 0.01);
}

// Figures: VISCERA_SELF_IMPACT="arm gap stretch rate [verbose]" runs one hairpin and prints it;
// VISCERA_SELF_IMPACT_CONTACTS and VISCERA_SELF_IMPACT_SIMULATION add [contacts] and
// [simulation] keys (e.g. "friction = 0.0", "implicit_scheme = \"backward_euler\""),
// VISCERA_SELF_IMPACT_SECONDS sets the duration, VISCERA_SELF_IMPACT_MOMENTUM_OFF=1 switches the
// safeguard off.
TEST(SelfImpactMomentum, Figures) {
  const char* only = std::getenv("VISCERA_SELF_IMPACT");
  if (!only)
    GTEST_SKIP() << "set VISCERA_SELF_IMPACT=\"arm gap stretch rate [verbose]\" to print a run";
  Hairpin h;
  int verbose = 0;
  std::sscanf(only, "%lf %lf %lf %lf %d", &h.arm, &h.gap, &h.stretch, &h.rate_hz, &verbose);
  if (const char* extra = std::getenv("VISCERA_SELF_IMPACT_CONTACTS"))
    h.contacts = std::string(extra) + "\n";
  if (const char* extra = std::getenv("VISCERA_SELF_IMPACT_SIMULATION"))
    h.simulation = std::string(extra) + "\n";
  h.momentum_kept = std::getenv("VISCERA_SELF_IMPACT_MOMENTUM_OFF") == nullptr;
  if (const char* seconds = std::getenv("VISCERA_SELF_IMPACT_SECONDS"))
    h.seconds = std::atof(seconds);
  const ImpactRun r = Simulate(h, verbose != 0);
  std::printf("%s\n", Describe(h, r).c_str());
}

}  // namespace
}  // namespace viscera::mechanics
