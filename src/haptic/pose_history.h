#pragma once
/// PoseHistory: the poses the loop sent lately, by sequence number, so that an answer can be
/// matched to the position it answers and to when that pose left. A fixed ring: a pose older
/// than `capacity` sends is forgotten (its answer is too old to render anyway).
#include <cstdint>
#include <vector>

#include "common/types.h"

namespace viscera::haptic {

class PoseHistory {
 public:
  struct Entry {
    int64_t seq = -1;
    Vec3 position = Vec3::Zero();  ///< m
    int64_t sent_ns = 0;           ///< monotonic
  };

  explicit PoseHistory(int capacity = 8192) : ring_(static_cast<size_t>(capacity)) {}

  void Add(int64_t seq, const Vec3& position, int64_t sent_ns) {
    ring_[Slot(seq)] = Entry{seq, position, sent_ns};
  }
  /// The pose with `seq`, or nullptr when it was never sent or is forgotten.
  const Entry* Find(int64_t seq) const {
    if (seq < 0) return nullptr;
    const Entry& e = ring_[Slot(seq)];
    return e.seq == seq ? &e : nullptr;
  }

 private:
  size_t Slot(int64_t seq) const { return static_cast<size_t>(seq) % ring_.size(); }
  std::vector<Entry> ring_;
};

}  // namespace viscera::haptic
