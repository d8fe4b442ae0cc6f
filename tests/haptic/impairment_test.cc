#include "haptic/impairment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace viscera::haptic {
namespace {

constexpr int64_t kMs = 1'000'000;

struct Delivered {
  int id;
  int64_t sent_ns, due_ns;
};

std::vector<Delivered> Transmit(const ImpairmentOptions& options, int n, int64_t gap_ns = kMs) {
  ImpairedChannel<std::pair<int, int64_t>> channel(options, 1);
  std::vector<Delivered> out;
  int64_t now = 0;
  for (int i = 0; i < n; ++i, now += gap_ns) {
    channel.Push(now, {i, now});
    channel.Deliver(now, [&](const std::pair<int, int64_t>& m, int64_t due) {
      out.push_back({m.first, m.second, due});
    });
  }
  channel.Deliver(now + 10'000 * kMs, [&](const std::pair<int, int64_t>& m, int64_t due) {
    out.push_back({m.first, m.second, due});
  });
  return out;
}

TEST(Impairment, NoneDeliversEverythingAtOnceInOrder) {
  const auto out = Transmit({}, 1000);
  ASSERT_EQ(out.size(), 1000u);
  for (int i = 0; i < 1000; ++i) {
    EXPECT_EQ(out[static_cast<size_t>(i)].id, i);
    EXPECT_EQ(out[static_cast<size_t>(i)].due_ns, out[static_cast<size_t>(i)].sent_ns);
  }
}

TEST(Impairment, DelaysWithinTheJitterBandAndReordersLikeANetwork) {
  const auto out = Transmit({.delay_s = 0.02, .jitter_s = 0.005, .loss = 0.0, .seed = 3}, 5000);
  ASSERT_EQ(out.size(), 5000u);
  int reordered = 0;
  double sum = 0.0;
  for (size_t i = 0; i < out.size(); ++i) {
    const int64_t delay = out[i].due_ns - out[i].sent_ns;
    EXPECT_GE(delay, 15 * kMs);
    EXPECT_LE(delay, 25 * kMs);
    sum += static_cast<double>(delay);
    if (i > 0 && out[i].id < out[i - 1].id) ++reordered;
    if (i > 0) {
      EXPECT_GE(out[i].due_ns, out[i - 1].due_ns);  // delivered in due order
    }
  }
  EXPECT_NEAR(sum / out.size() / kMs, 20.0, 0.2);  // uniform jitter: mean is the delay
  EXPECT_GT(reordered, 100);  // 1 ms apart with +-5 ms of jitter: often overtaken
}

TEST(Impairment, LosesTheGivenFractionReproduciblyPerSeed) {
  const ImpairmentOptions a{.delay_s = 0.0, .jitter_s = 0.0, .loss = 0.1, .seed = 11};
  const auto first = Transmit(a, 100000);
  const auto again = Transmit(a, 100000);
  // binomial: 10 % of 100000 lost, sigma = 95; allow 5 sigma
  EXPECT_NEAR(100000.0 - first.size(), 10000.0, 475.0);
  ASSERT_EQ(first.size(), again.size());
  for (size_t i = 0; i < first.size(); ++i) ASSERT_EQ(first[i].id, again[i].id);
  ImpairmentOptions b = a;
  b.seed = 12;
  const auto other = Transmit(b, 100000);
  int differ = 0;
  for (size_t i = 0; i < std::min(first.size(), other.size()); ++i)
    differ += first[i].id != other[i].id;
  EXPECT_GT(differ, 0);
}

TEST(Impairment, RejectsBadOptions) {
  EXPECT_THROW((ImpairmentOptions{.delay_s = -1.0}.Validate()), InputError);
  EXPECT_THROW((ImpairmentOptions{.loss = 1.5}.Validate()), InputError);
}

}  // namespace
}  // namespace viscera::haptic
