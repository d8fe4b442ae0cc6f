#include "session/outbox.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>

namespace viscera::session {

Outbox::Outbox(bus::LcmBus* bus, Recorder* recorder, Channels channels, int realtime_priority)
    : bus_(bus), recorder_(recorder), channels_(std::move(channels)) {
  thread_ = std::thread([this, realtime_priority] { Run(realtime_priority); });
}

Outbox::~Outbox() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void Outbox::Flush() { wake_.notify_one(); }

void Outbox::Drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.notify_one();
  idle_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

int64_t Outbox::max_depth() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return max_depth_;
}

int64_t Outbox::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

int64_t Outbox::nonfinite() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return nonfinite_;
}

bool Outbox::PushBounded(std::deque<Item>* queue, Item item, size_t max) {
  bool dropped = false;
  if (queue->size() >= max && !queue->empty()) {
    const auto force = std::find_if(queue->begin(), queue->end(), [](const Item& queued) {
      return std::holds_alternative<viscera_proto::force_feedback_t>(queued);
    });
    queue->erase(force != queue->end() ? force : queue->begin());
    dropped = true;
  }
  queue->push_back(std::move(item));
  return dropped;
}

void Outbox::Send(const Item& item) {
  // Publish and Write never throw (failures are counted by the bus and the recorder)
  std::visit(
      [this](const auto& msg) {
        using Msg = std::decay_t<decltype(msg)>;
        const std::string* channel = &channels_.force;
        if constexpr (std::is_same_v<Msg, viscera_proto::skeleton_state_t>)
          channel = &channels_.skeleton;
        if constexpr (std::is_same_v<Msg, viscera_proto::session_status_t>)
          channel = &channels_.status;
        if constexpr (std::is_same_v<Msg, viscera_proto::step_record_t>) {
          channel = &channels_.step;
        } else {
          bus_->Publish(*channel, msg);
        }
        if (recorder_ != nullptr) {
          recorder_->Write(*channel, msg, msg.header.utime);
          // a status is the moment to push the record to the kernel (also every 50 ms)
          if constexpr (std::is_same_v<Msg, viscera_proto::session_status_t>) recorder_->Flush();
        }
      },
      item);
}

void Outbox::Run(int realtime_priority) {
  if (realtime_priority > 0) {
    sched_param param{};
    param.sched_priority = realtime_priority;
    pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);  // best effort, as the loop's
  }
  std::deque<Item> batch;
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
    if (queue_.empty() && stop_) break;
    batch.swap(queue_);
    busy_ = true;
    lock.unlock();
    for (const Item& item : batch) Send(item);
    batch.clear();
    lock.lock();
    busy_ = false;
    if (queue_.empty()) idle_.notify_all();
  }
}

}  // namespace viscera::session
