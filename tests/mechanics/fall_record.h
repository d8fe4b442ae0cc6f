#pragma once
// A fall without input, recorded step by step: the deepest pair and the total energy (kinetic,
// gravity, elastic and contact: ComputeEnergies with the interactions) after every step. Used by
// the measurements of whole falls (the peers' benchmark, the 55 cm drop's energy).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "collision/obstacle.h"
#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {

/// `params` with its coil moved up or down so that the centre line's lowest control point starts
/// `height` above z = 0 (tests/mechanics/impact_test.cc's convention for its drops).
inline ModelParams DroppedFrom(ModelParams params, double height) {
  const double lowest = params.initial_q.col(2).minCoeff();
  params.initial_q.col(2).array() += height - lowest;
  return params;
}

struct FallRecord {
  double radius = 0.0;
  double step_size = 0.0;
  Energies start_terms;           // at release
  double start_energy = 0.0;      // J, at release: start_terms' total
  std::vector<double> depth;      // after each step: the deepest pair, fraction of R (0 when none)
  std::vector<std::string> what;  // what that pair touched ("self", "environment")
  std::vector<double> floor;  // after each step: the deepest sphere into an obstacle, fraction of R
  std::vector<Energies> terms;  // after each step
  std::vector<double> energy;   // J, after each step: terms' total
  int max_substeps = 0;

  double Seconds(int step) const { return (step + 1) * step_size; }
  int DeepestStep() const {
    return static_cast<int>(std::max_element(depth.begin(), depth.end()) - depth.begin());
  }
  double Deepest() const { return depth[DeepestStep()]; }
  /// The largest gain of total energy from one step to the next (the release counts as step -1).
  double LargestGain(int* at = nullptr) const {
    double gain = -INFINITY, previous = start_energy;
    for (size_t k = 0; k < energy.size(); ++k) {
      if (energy[k] - previous > gain) {
        gain = energy[k] - previous;
        if (at) *at = static_cast<int>(k);
      }
      previous = energy[k];
    }
    return gain;
  }
};

/// One line of figures: the deepest pair (when, what), the deepest into an obstacle, both after
/// the last step, the worst one-step energy gain split by term, and the sub-steps.
inline std::string Describe(const FallRecord& r) {
  const int deepest = r.DeepestStep();
  const int floor =
      static_cast<int>(std::max_element(r.floor.begin(), r.floor.end()) - r.floor.begin());
  int at = 0;
  const double gain = r.LargestGain(&at);
  const Energies before = at > 0 ? r.terms[at - 1] : r.start_terms, after = r.terms[at];
  const double elastic_before =
      before.stretch + before.bend + before.continuous + before.attachment + before.mesentery;
  const double elastic_after =
      after.stretch + after.bend + after.continuous + after.attachment + after.mesentery;
  char line[768];
  std::snprintf(line, sizeof line,
                "deepest pair %6.2f %% R at %.3f s (%s), into the floor %6.2f %% R at %.3f s; at "
                "the end %.2f / %.2f %% R; "
                "worst one-step energy gain %+.2e J (%+.1e of the start %.3f J) at %.3f s [kinetic "
                "%+.1e, gravity %+.1e, "
                "elastic %+.1e (stretch %+.1e, bend %+.1e, continuous %+.1e), contact %+.1e]; end "
                "%.3f J; max sub-steps %d",
                100.0 * r.depth[deepest], r.Seconds(deepest), r.what[deepest].c_str(),
                100.0 * r.floor[floor], r.Seconds(floor), 100.0 * r.depth.back(),
                100.0 * r.floor.back(), gain, gain / r.start_energy, r.start_energy, r.Seconds(at),
                after.kinetic - before.kinetic, after.gravity - before.gravity,
                elastic_after - elastic_before, after.stretch - before.stretch,
                after.bend - before.bend, after.continuous - before.continuous,
                after.contact - before.contact, r.energy.back(), r.max_substeps);
  return line;
}

inline FallRecord RecordFall(const ModelParams& params, double seconds) {
  const Model model(params);
  State state = InitialState(model);
  Workspace workspace(model);
  Interactions* in = workspace.interactions();
  FallRecord r;
  r.radius = params.radius;
  r.step_size = model.step_size();
  r.start_terms = ComputeEnergies(model, state.q, state.qd, in);
  r.start_energy = r.start_terms.total();
  const int steps = static_cast<int>(std::lround(seconds * params.rate_hz));
  for (int k = 0; k < steps; ++k) {
    Step(model, {}, &state, &workspace);
    const double clearance = state.contacts.min_clearance;
    r.depth.push_back(std::isnan(clearance) ? 0.0 : std::max(0.0, -clearance / params.radius));
    r.what.emplace_back(state.contacts.deepest);
    double floor = 0.0;  // the chain is placed at the step's end (Interactions::EndStep)
    for (const collision::Sphere& s : in->chain().spheres()) {
      for (const collision::Obstacle& o : params.obstacles)
        floor = std::max(floor, in->chain().radius() - collision::SignedDistance(o, s.centre));
    }
    r.floor.push_back(floor / params.radius);
    r.terms.push_back(ComputeEnergies(model, state.q, state.qd, in));
    r.energy.push_back(r.terms.back().total());
    r.max_substeps = std::max(r.max_substeps, state.substeps);
  }
  return r;
}

}  // namespace viscera::mechanics
