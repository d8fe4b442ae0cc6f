#include "bus/replay_guard.h"

#include <cstdlib>
#include <cstring>

#include "common/check.h"

namespace viscera::bus {

ReplayGuard::ReplayGuard(int64_t max_skew_us, size_t max_entries)
    : max_skew_us_(max_skew_us), max_entries_(max_entries) {
  ThrowUnless(max_skew_us_ > 0, "clock-skew bound must be > 0 us, got ", max_skew_us_);
  ThrowUnless(max_entries_ > 0, "replay guard needs room for at least one sender");
}

void ReplayGuard::Expire(int64_t now_us) {
  std::erase_if(windows_, [&](const auto& entry) {
    return now_us - entry.second.last_us > 2 * max_skew_us_;
  });
  next_full_sweep_us_ = now_us + 1'000'000;
}

void ReplayGuard::SweepSome(int64_t now_us) {
  const size_t buckets = windows_.bucket_count();
  for (int n = 0; n < kBucketsPerCheck; ++n) {
    cursor_ = (cursor_ + 1) % buckets;
    for (auto it = windows_.cbegin(cursor_); it != windows_.cend(cursor_); ++it) {
      if (now_us - it->second.last_us > 2 * max_skew_us_) idle_.push_back(&it->first);
    }
    for (const std::string* key : idle_) windows_.erase(windows_.find(*key));
    idle_.clear();
  }
}

ReplayGuard::Verdict ReplayGuard::Check(int64_t sender, const std::string& channel, int64_t seq,
                                        int64_t utime, int64_t now_us) {
  if (sender == 0 || seq < 0) return Verdict::kNoSender;
  // |now - utime| without overflow for any utime an attacker may put there
  if (utime < now_us - max_skew_us_ || utime > now_us + max_skew_us_) return Verdict::kStale;
  if (utime < epoch_us_) return Verdict::kBeforeEpoch;
  SweepSome(now_us);

  key_.resize(sizeof(sender));
  std::memcpy(key_.data(), &sender, sizeof(sender));
  key_ += channel;
  auto it = windows_.find(key_);
  if (it == windows_.end()) {
    if (windows_.size() >= max_entries_) {
      if (now_us >= next_full_sweep_us_) Expire(now_us);
      if (windows_.size() >= max_entries_) return Verdict::kFull;
    }
    it = windows_.emplace(key_, Window{}).first;
  }
  Window& w = it->second;
  if (seq > w.highest) {
    const int64_t shift = w.highest < 0 ? kWindow : seq - w.highest;
    w.seen = shift >= kWindow ? 0 : w.seen << shift;
    w.seen |= 1;
    w.highest = seq;
  } else {
    const int64_t behind = w.highest - seq;
    if (behind >= kWindow) return Verdict::kReplayed;
    const uint64_t bit = uint64_t{1} << behind;
    if ((w.seen & bit) != 0) return Verdict::kReplayed;
    w.seen |= bit;
  }
  w.last_us = now_us;
  return Verdict::kAccepted;
}

std::string ReplayGuard::Explain(Verdict verdict, int64_t seq, int64_t utime,
                                 int64_t now_us) const {
  switch (verdict) {
    case Verdict::kAccepted: return "";
    case Verdict::kReplayed:
      return Cat("replayed: sequence ", seq,
                 " of this sender was already seen (or is older than the last ", kWindow, ")");
    case Verdict::kStale:
      // in double: a hostile utime (INT64_MIN) overflows the difference of the integers
      return Cat("stale: sent ", (static_cast<double>(now_us) - static_cast<double>(utime)) * 1e-6,
                 " s before the server's clock (bound ", static_cast<double>(max_skew_us_) * 1e-6,
                 " s; are the clocks synchronised?)");
    case Verdict::kNoSender:
      return "no sender id or a negative sequence: cannot be checked for replay";
    case Verdict::kBeforeEpoch:
      return Cat("stale: sent ",
                 (static_cast<double>(epoch_us_) - static_cast<double>(utime)) * 1e-6,
                 " s before this server started (a message from before a restart is never taken)");
    case Verdict::kFull:
      return Cat("too many senders (", max_entries_, ") within the freshness bound");
  }
  return "";
}

}  // namespace viscera::bus
