#include "session/snapshot.h"

#include <chrono>

#include "common/check.h"

namespace viscera::session {

SnapshotExchange::SnapshotExchange() {
  for (int i = 0; i < 3; ++i) pool_.push_back(std::make_unique<Buffer>());
}

SnapshotExchange::~SnapshotExchange() {
  for (const std::unique_ptr<Buffer>& b : pool_) VISCERA_DEMAND(b->readers.load() == 0);
}

void SnapshotExchange::Publish(const mechanics::State& state,
                               const std::vector<std::pair<double, double>>& damaged) {
  Buffer* free = nullptr;
  for (const std::unique_ptr<Buffer>& b : pool_) {
    if (b.get() != latest_ && b->readers.load(std::memory_order_acquire) == 0) {
      free = b.get();
      break;
    }
  }
  if (free == nullptr) {  // more readers than foreseen hold snapshots
    pool_.push_back(std::make_unique<Buffer>());
    free = pool_.back().get();
  }
  Snapshot& next = free->snapshot;
  next.step = state.steps;
  next.t = state.t;
  next.wall_utime = std::chrono::duration_cast<std::chrono::microseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
  next.q = state.q;  // same size: no allocation
  next.tools = state.tools;
  next.contacts = state.contacts;
  next.damaged.assign(damaged.begin(), damaged.end());
  // never wait for a reader (the render thread runs SCHED_IDLE and may be preempted while it
  // holds the lock): if one holds it, this snapshot is skipped and its buffer refilled next time
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (lock.owns_lock()) latest_ = free;
}

std::shared_ptr<const Snapshot> SnapshotExchange::Latest() const {
  Buffer* buffer = nullptr;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (latest_ == nullptr) return nullptr;
    buffer = latest_;
    buffer->readers.fetch_add(1, std::memory_order_relaxed);
  }
  // the reader's last reads happen before this release; Publish's acquire load sees them
  return std::shared_ptr<const Snapshot>(&buffer->snapshot, [buffer](const Snapshot*) {
    buffer->readers.fetch_sub(1, std::memory_order_release);
  });
}

}  // namespace viscera::session
