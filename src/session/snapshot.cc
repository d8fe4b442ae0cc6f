#include "session/snapshot.h"

#include <atomic>
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
  // use_count() is a relaxed load: order the last reader's reads before our writes
  std::atomic_thread_fence(std::memory_order_acquire);
  Snapshot& next = **free;
  next.step = state.steps;
  next.t = state.t;
  next.wall_utime = std::chrono::duration_cast<std::chrono::microseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
  next.q = state.q;  // same size: no allocation
  next.tools = state.tools;
  next.contacts = state.contacts;
  // never wait for a reader (the render thread runs SCHED_IDLE and may be preempted while it
  // holds the lock): if one holds it, this snapshot is skipped and its buffer refilled next time
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (lock.owns_lock()) latest_ = *free;
}

std::shared_ptr<const Snapshot> SnapshotExchange::Latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

}  // namespace viscera::session
