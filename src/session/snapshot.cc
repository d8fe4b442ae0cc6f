#include "session/snapshot.h"

#include <chrono>

namespace viscera::session {

void SnapshotExchange::Publish(const mechanics::State& state) {
  // the spare is ours alone once nobody else holds it (use_count 1): fill it in place
  std::shared_ptr<Snapshot> next = std::move(spare_);
  if (next == nullptr || next.use_count() != 1) next = std::make_shared<Snapshot>();
  next->step = state.steps;
  next->t = state.t;
  next->wall_utime = std::chrono::duration_cast<std::chrono::microseconds>(
                         std::chrono::system_clock::now().time_since_epoch())
                         .count();
  next->q = state.q;  // same size: no allocation
  next->tools = state.tools;
  next->contacts = state.contacts;
  std::shared_ptr<const Snapshot> previous;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    previous = std::move(latest_);
    latest_ = std::move(next);
  }
  // the previous one becomes the spare; reused only if no reader still holds it
  spare_ = std::const_pointer_cast<Snapshot>(previous);
}

std::shared_ptr<const Snapshot> SnapshotExchange::Latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

}  // namespace viscera::session
