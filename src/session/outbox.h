#pragma once
/// Outbox: the session's output thread. The mechanics thread hands it every message it
/// produces (force feedback, skeleton, status, step records) and goes back to its
/// deadlines; the output thread publishes them on the bus and writes them to the record,
/// in the order they were handed over. Publishing on LCM (a sendto on a multicast socket)
/// and writing the record (stdio) can block for milliseconds on a busy machine
/// (docs/server-benchmarks.md measured 1-5 ms stalls in sendto); here they cannot delay a step.
/// The queue is bounded (kMaxQueued): when the output falls behind, the oldest force is
/// dropped (a newer one for the same tool supersedes it), or with no force queued the oldest
/// message; and no message with a non-finite number is ever sent. Both are counted.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <variant>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/session_status_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/step_record_t.hpp>

#include "bus/lcm_bus.h"
#include "session/finite_message.h"
#include "session/recorder.h"

namespace viscera::session {

class Outbox {
 public:
  /// Messages waiting at most (about 4 s of a 1 kHz session with one tool).
  static constexpr size_t kMaxQueued = 8192;

  /// Where each kind goes: published on its channel (step records are never published)
  /// and, with a recorder, recorded.
  struct Channels {
    std::string force, skeleton, status, step;
  };

  /// @pre bus outlives the outbox; recorder may be null (no record).
  Outbox(bus::LcmBus* bus, Recorder* recorder, Channels channels, int realtime_priority);
  /// Sends what is queued, then stops the thread.
  ~Outbox();
  Outbox(const Outbox&) = delete;
  Outbox& operator=(const Outbox&) = delete;

  using Item = std::variant<viscera_proto::force_feedback_t, viscera_proto::skeleton_state_t,
                            viscera_proto::session_status_t, viscera_proto::step_record_t>;
  /// Appends `item` to `queue`; when it already holds `max` items, first drops the oldest
  /// force, or with none the oldest item. @return true when one was dropped.
  static bool PushBounded(std::deque<Item>* queue, Item item, size_t max);

  /// Queue a message (mechanics thread). Call Flush() once per loop iteration to wake the
  /// output thread.
  void Push(const viscera_proto::force_feedback_t& msg) { PushItem(msg); }
  void Push(const viscera_proto::skeleton_state_t& msg) { PushItem(msg); }
  void Push(const viscera_proto::session_status_t& msg) { PushItem(msg); }
  void Push(const viscera_proto::step_record_t& msg) { PushItem(msg); }
  void Flush();

  /// Blocks until everything queued so far is sent. Any thread.
  void Drain();

  /// Most messages that ever waited at once (a sign of a stalled output).
  int64_t max_depth() const;
  /// Messages dropped because the queue was full, and forces or skeletons refused because a
  /// number in them was not finite.
  int64_t dropped() const;
  int64_t nonfinite() const;

 private:
  template <typename Msg>
  void PushItem(const Msg& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!AllFinite(msg)) {
      ++nonfinite_;
      return;
    }
    if (PushBounded(&queue_, msg, kMaxQueued)) ++dropped_;
    if (static_cast<int64_t>(queue_.size()) > max_depth_)
      max_depth_ = static_cast<int64_t>(queue_.size());
  }
  void Run(int realtime_priority);
  void Send(const Item& item);

  bus::LcmBus* bus_;
  Recorder* recorder_;
  Channels channels_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::deque<Item> queue_;
  bool busy_ = false;
  bool stop_ = false;
  int64_t max_depth_ = 0;
  int64_t dropped_ = 0;
  int64_t nonfinite_ = 0;
  std::thread thread_;
};

}  // namespace viscera::session
