#include "bus/replay_guard.h"

#include <gtest/gtest.h>

namespace viscera::bus {
namespace {

using V = ReplayGuard::Verdict;
constexpr int64_t kSkew = 10'000'000;  // 10 s
constexpr int64_t kNow = 1'700'000'000'000'000;

TEST(ReplayGuard, AcceptsEachSequenceOnceAndRefusesItsReplay) {
  ReplayGuard guard(kSkew);
  for (int64_t seq = 0; seq < 5; ++seq)
    EXPECT_EQ(guard.Check(7, "A", seq, kNow, kNow), V::kAccepted);
  for (int64_t seq = 0; seq < 5; ++seq)
    EXPECT_EQ(guard.Check(7, "A", seq, kNow, kNow), V::kReplayed) << seq;
  EXPECT_EQ(guard.Check(7, "A", 5, kNow, kNow), V::kAccepted);
}

TEST(ReplayGuard, TakesLateArrivalsWithinTheWindowOnceAndNothingOlder) {
  ReplayGuard guard(kSkew);
  EXPECT_EQ(guard.Check(1, "A", 100, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(1, "A", 98, kNow, kNow), V::kAccepted);  // reordered on the way
  EXPECT_EQ(guard.Check(1, "A", 98, kNow, kNow), V::kReplayed);
  EXPECT_EQ(guard.Check(1, "A", 100 - ReplayGuard::kWindow + 1, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(1, "A", 100 - ReplayGuard::kWindow, kNow, kNow),
            V::kReplayed);  // too old to tell
  // a jump beyond the window forgets the old bits, not the order
  EXPECT_EQ(guard.Check(1, "A", 1000, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(1, "A", 999, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(1, "A", 100, kNow, kNow), V::kReplayed);
}

TEST(ReplayGuard, SendersAndChannelsHaveTheirOwnSequences) {
  ReplayGuard guard(kSkew);
  EXPECT_EQ(guard.Check(1, "A", 0, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(2, "A", 0, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(1, "B", 0, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.entries(), 3u);
}

TEST(ReplayGuard, RefusesStaleAndFutureTimesAndMessagesWithoutASender) {
  ReplayGuard guard(kSkew);
  EXPECT_EQ(guard.Check(1, "A", 0, kNow - kSkew - 1, kNow), V::kStale);
  EXPECT_EQ(guard.Check(1, "A", 0, kNow + kSkew + 1, kNow), V::kStale);
  EXPECT_EQ(guard.Check(1, "A", 0, INT64_MIN, kNow), V::kStale);  // no overflow
  EXPECT_EQ(guard.Check(1, "A", 0, kNow - kSkew, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(0, "A", 0, kNow, kNow), V::kNoSender);
  EXPECT_EQ(guard.Check(1, "A", -1, kNow, kNow), V::kNoSender);
  EXPECT_NE(guard.Explain(V::kStale, 0, kNow - 2 * kSkew, kNow).find("stale"), std::string::npos);
  // the explanation of a hostile time: no overflow (UBSan's run of this test caught it in
  // Explain; the fuzzer found it through the server)
  EXPECT_NE(guard.Explain(V::kStale, 0, INT64_MIN, kNow).find("stale: sent 9.2"),
            std::string::npos);
  EXPECT_NE(guard.Explain(V::kStale, 0, INT64_MAX, kNow).find("stale: sent -9.2"),
            std::string::npos);
  EXPECT_NE(guard.Explain(V::kReplayed, 4, kNow, kNow).find("replayed"), std::string::npos);
}

TEST(ReplayGuard, ForgetsIdleSendersOnlyOnceTheirMessagesAreStale) {
  ReplayGuard guard(kSkew, /*max_entries=*/2);
  EXPECT_EQ(guard.Check(1, "A", 5, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(2, "A", 5, kNow, kNow), V::kAccepted);
  EXPECT_EQ(guard.Check(3, "A", 0, kNow, kNow), V::kFull);  // full while both may still replay
  const int64_t later = kNow + 2 * kSkew + 1;
  EXPECT_EQ(guard.Check(3, "A", 0, later, later), V::kAccepted);  // 1 and 2 expired
  // the idle ones go a few buckets per message
  for (int64_t seq = 1; seq < 100 && guard.entries() > 1; ++seq)
    guard.Check(3, "A", seq, later, later);
  EXPECT_EQ(guard.entries(), 1u);
  // sender 1's old message is refused by its age now that its window is gone
  EXPECT_EQ(guard.Check(1, "A", 5, kNow, later), V::kStale);
}

// Idle senders go a few buckets per message, never in one sweep of the whole table (rotating
// sender ids made a command wait 0.84 s behind sweeps): 1000 idle entries are all gone after
// one pass of the buckets, each message having looked at kBucketsPerCheck of them.
TEST(ReplayGuard, SweepsIdleSendersIncrementally) {
  ReplayGuard guard(kSkew);
  for (int64_t sender = 1; sender <= 1000; ++sender)
    ASSERT_EQ(guard.Check(sender, "A", 0, kNow, kNow), V::kAccepted);
  const int64_t later = kNow + 2 * kSkew + 1;
  EXPECT_EQ(guard.Check(5000, "A", 0, later, later), V::kAccepted);
  EXPECT_GT(guard.entries(), 900u);  // one message swept only a few buckets
  for (int64_t seq = 1; seq < 2000 && guard.entries() > 1; ++seq)
    guard.Check(5000, "A", seq, later, later);
  EXPECT_EQ(guard.entries(), 1u);
}

// A restart forgets every window; the epoch keeps a message captured before it stale.
TEST(ReplayGuard, RefusesWhatWasSentBeforeItsEpoch) {
  ReplayGuard guard(kSkew);
  guard.SetEpoch(kNow);
  EXPECT_EQ(guard.Check(1, "A", 0, kNow - 1, kNow + 1000), V::kBeforeEpoch);
  EXPECT_NE(guard.Explain(V::kBeforeEpoch, 0, kNow - 1, kNow).find("before this server started"),
            std::string::npos);
  EXPECT_EQ(guard.Check(1, "A", 0, kNow, kNow + 1000), V::kAccepted);
}

}  // namespace
}  // namespace viscera::bus
