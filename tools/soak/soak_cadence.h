#pragma once
// Which faults a soak cycle carries, by its number (1-based). The loop and the memory check's
// warm-up both read it: the server counts as warm only once every kind of cycle has run.
#include <cstdint>

namespace viscera::soak {

/// Sessions created on even cycles stream frames (their render contexts compile the textures'
/// shader programs when a material first uses one).
constexpr bool FramesOn(int64_t cycle) { return cycle % 2 == 0; }

/// Every 5th cycle sends the hostile scenes (SendMalformedScenes).
constexpr bool HostileScenes(int64_t cycle) { return cycle % 5 == 1; }

/// Every 10th cycle creates a scene that blows up (UnstableScene) and waits for its recovery.
constexpr bool BlowUp(int64_t cycle) { return cycle % 10 == 3; }

/// Cycles after which the kinds above repeat: each runs at least once in any run of this many
/// consecutive cycles (5 with frames, 2 with hostile scenes, 1 blow-up).
constexpr int64_t kCadencePeriod = 10;

}  // namespace viscera::soak
