#pragma once
/// Snapshot hand-off from the mechanics thread to readers (the session's skin/render thread,
/// tests): an immutable copy of the skeleton, published as a
/// shared_ptr<const Snapshot>. The mechanics thread never shares its mutable state; a reader
/// keeps its snapshot as long as it likes while newer ones are published.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "mechanics/state.h"

namespace viscera::session {

struct Snapshot {
  int64_t step = 0;
  double t = 0.0;                           ///< simulated time (s)
  int64_t wall_utime = 0;                   ///< wall clock when taken (us since the Unix epoch)
  Points q;                                 ///< control points (m), #N by 3
  std::vector<mechanics::ToolState> tools;  ///< tool tips, jaws, forces
  mechanics::ContactStats contacts;
  /// Running the bowel's damaged parts as ranges [from, to] of the curve parameter s (0..1):
  /// drawn in the damage colour (empty without damage or without [running]).
  std::vector<std::pair<double, double>> damaged;
};

class SnapshotExchange {
 public:
  SnapshotExchange();
  /// @pre no reader still holds a snapshot of this exchange (checked).
  ~SnapshotExchange();
  SnapshotExchange(const SnapshotExchange&) = delete;
  SnapshotExchange& operator=(const SnapshotExchange&) = delete;

  /// Publishes a copy of `state` (mechanics thread), unless a reader holds the lock at this
  /// very moment: then this snapshot is skipped (the next step's will do), so the mechanics
  /// thread never waits for a reader. It fills a buffer that is neither the latest nor held
  /// by a reader: with one reader (the render thread) holding one snapshot at a time, three
  /// buffers always leave one free, so publishing every step never allocates (but for the
  /// damaged ranges, when they outgrow the buffer's: a few times in a session at most).
  void Publish(const mechanics::State& state,
               const std::vector<std::pair<double, double>>& damaged = {});

  /// The latest snapshot, or nullptr before the first; it stays unchanged while held. Any
  /// thread.
  std::shared_ptr<const Snapshot> Latest() const;

 private:
  struct Buffer {
    Snapshot snapshot;
    // Readers holding it: taken under mutex_ (only on the latest buffer), given back with
    // release order, so the mechanics thread's acquire load orders their reads before its
    // refill.
    std::atomic<int> readers{0};
  };

  mutable std::mutex mutex_;
  Buffer* latest_ = nullptr;                   // written by the mechanics thread under mutex_
  std::vector<std::unique_ptr<Buffer>> pool_;  // mechanics thread only; grows past 3 only
                                               // when readers hold more than one each
};

}  // namespace viscera::session
