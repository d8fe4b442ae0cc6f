#include "session/snapshot.h"

#include <chrono>

namespace viscera::session {

void SnapshotExchange::Publish(const mechanics::State& state) {
  // a buffer only the pool holds (use_count 1: neither latest_ nor a reader) is ours to fill
  std::shared_ptr<Snapshot>* free = nullptr;
  for (std::shared_ptr<Snapshot>& p : pool_) {
    if (p == nullptr || p.use_count() == 1) {
      free = &p;
      break;
    }
  }
  if (free == nullptr) {  // more readers than the pool foresees: the oldest entry is theirs now
    free = &pool_[next_evicted_];
    next_evicted_ = (next_evicted_ + 1) % pool_.size();
  }
  if (*free == nullptr || free->use_count() != 1) *free = std::make_shared<Snapshot>();
  Snapshot& next = **free;
  next.step = state.steps;
  next.t = state.t;
  next.wall_utime = std::chrono::duration_cast<std::chrono::microseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
  next.q = state.q;  // same size: no allocation
  next.tools = state.tools;
  next.contacts = state.contacts;
  std::lock_guard<std::mutex> lock(mutex_);
  latest_ = *free;
}

std::shared_ptr<const Snapshot> SnapshotExchange::Latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

}  // namespace viscera::session
