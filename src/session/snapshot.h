#pragma once
/// Snapshot hand-off from the mechanics thread to readers (the session's skin/render thread,
/// tests): an immutable copy of the skeleton, published as a
/// shared_ptr<const Snapshot>. The mechanics thread never shares its mutable state; a reader
/// keeps its snapshot as long as it likes while newer ones are published.
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "mechanics/state.h"

namespace viscera::session {

struct Snapshot {
  int64_t step = 0;
  double t = 0.0;                          ///< simulated time (s)
  int64_t wall_utime = 0;                  ///< wall clock when taken (us since the Unix epoch)
  Points q;                                ///< control points (m), #N by 3
  std::vector<mechanics::ToolState> tools;  ///< tool tips, jaws, forces
  mechanics::ContactStats contacts;
};

class SnapshotExchange {
 public:
  /// Publishes a copy of `state` (mechanics thread), unless a reader holds the lock at this
  /// very moment: then this snapshot is skipped (the next step's will do), so the mechanics
  /// thread never waits for a reader. Reuses a snapshot no reader holds any more: with one
  /// reader (the render thread) holding one snapshot at a time, the three buffers of the
  /// pool always leave one free, so publishing every step never allocates.
  void Publish(const mechanics::State& state);

  /// The latest snapshot, or nullptr before the first. Any thread.
  std::shared_ptr<const Snapshot> Latest() const;

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const Snapshot> latest_;
  std::array<std::shared_ptr<Snapshot>, 3> pool_;  // mechanics thread only
  size_t next_evicted_ = 0;
};

}  // namespace viscera::session
