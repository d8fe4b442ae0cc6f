#pragma once
/// ReplayGuard: refuses replayed and stale session-changing messages (docs/security.md).
///
/// Every such message carries header.sender (a random id its sender keeps), header.seq
/// (+1 per message of that sender on that channel) and header.utime (its send time). The
/// guard keeps, per (sender, channel), the highest sequence accepted and which of the
/// `kWindow` below it were seen (the IPsec anti-replay window): a sequence seen before, or
/// older than the window, is a replay. A utime further than `max_skew_us` from the
/// receiver's clock is stale. Entries idle for twice the skew bound are forgotten (any
/// message they could still stop is stale by then), a few hash buckets per message, so no
/// message pays for a sweep of the whole table; a full table is swept whole at most once a
/// second (a flood of new senders made every message sweep 65536 entries). Under a MAC the three
/// fields are authentic, so an injector can neither rewind nor advance a window.
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace viscera::bus {

class ReplayGuard {
 public:
  /// Sequences accepted out of order at most this far below the highest one.
  static constexpr int kWindow = 64;
  /// Hash buckets examined for idle entries per message checked.
  static constexpr int kBucketsPerCheck = 4;

  enum class Verdict { kAccepted, kReplayed, kStale, kNoSender, kFull, kBeforeEpoch };

  /// @param max_skew_us clock-skew bound (µs, > 0): how far a sender's clock may be from ours.
  /// @param max_entries (sender, channel) pairs kept at most; beyond it, new senders are
  ///        refused (kFull) until old ones expire.
  explicit ReplayGuard(int64_t max_skew_us, size_t max_entries = 1 << 16);

  /// Messages sent (utime) before `epoch_us` are refused (kBeforeEpoch): the server's start.
  /// The windows live in memory only, so without it a message captured before a restart was
  /// new to the restarted server and accepted within the skew bound.
  void SetEpoch(int64_t epoch_us) { epoch_us_ = epoch_us; }

  /// Decides on one message and, when accepted, remembers its sequence. `now_us` is the
  /// receiver's wall clock (µs since the epoch). Call only once the message is otherwise
  /// authentic (valid MAC or token): an accepted sequence moves the window.
  Verdict Check(int64_t sender, const std::string& channel, int64_t seq, int64_t utime,
                int64_t now_us);

  /// Why a verdict refused a message, for replies and status ("" for kAccepted).
  std::string Explain(Verdict verdict, int64_t seq, int64_t utime, int64_t now_us) const;

  size_t entries() const { return windows_.size(); }
  int64_t max_skew_us() const { return max_skew_us_; }

 private:
  struct Window {
    int64_t highest = -1;
    uint64_t seen = 0;  // bit i: highest - i was accepted
    int64_t last_us = 0;
  };
  void Expire(int64_t now_us);
  void SweepSome(int64_t now_us);

  int64_t max_skew_us_;
  size_t max_entries_;
  int64_t epoch_us_ = 0;
  std::unordered_map<std::string, Window> windows_;
  std::string key_;  // reused: no allocation per message once grown
  int64_t next_full_sweep_us_ = 0;
  size_t cursor_ = 0;                     // the next bucket SweepSome examines
  std::vector<const std::string*> idle_;  // reused: the keys SweepSome erases
};

}  // namespace viscera::bus
