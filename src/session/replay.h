#pragma once
/// Replay of a session record: rebuilds the model from the scene kept in the record and
/// runs the recorded inputs (step_record_t, in order) through the same Stepper the live
/// session used, so the trajectory comes out bit for bit the same. It checks itself
/// against the skeleton states and every force feedback message the session recorded.
#include <cstdint>
#include <functional>
#include <string>

#include "mechanics/state.h"
#include "scene/scene.h"

namespace viscera::session {

struct ReplayResult {
  int64_t session_id = 0;
  std::string scene;               ///< scene label
  double rate_hz = 0.0;            ///< mechanics rate (Hz)
  int64_t steps = 0;               ///< steps replayed
  int64_t resets = 0;              ///< reset commands replayed
  int64_t recoveries = 0;          ///< blow-ups recovered during replay
  int64_t skeletons_compared = 0;  ///< recorded skeleton states checked
  /// Largest distance between a replayed and a recorded control point (m), over every
  /// recorded skeleton state; 0 for an exact replay.
  double max_deviation = 0.0;
  int64_t forces_compared = 0;  ///< recorded force_feedback_t messages checked
  /// Recorded force messages whose mechanics fields (force_feedback.h) differ in any bit
  /// from the replay's; 0 for an exact replay.
  int64_t force_mismatches = 0;
  std::string first_force_mismatch;  ///< what differed first ("" if nothing did)
  mechanics::State final_state;
};

/// Called after every replayed step (and reset) with the model and the state, e.g. to write
/// a trace. It must not keep references past the call.
using ReplayObserver =
    std::function<void(const mechanics::Model& model, const mechanics::State& state)>;

/// Replays the record at `path`. Only the first session in the file is replayed; its scene
/// is read within `limits` (none by default: records are local files; a record from
/// elsewhere is as hostile as a scene from the network).
/// @throws InputError when the file cannot be read, holds no scene record, or a record
///         is malformed.
ReplayResult ReplayRecord(const std::string& path, const ReplayObserver& on_step = nullptr,
                          const scene::SceneLimits& limits = scene::SceneLimits{});

}  // namespace viscera::session
