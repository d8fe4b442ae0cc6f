#include "session/snapshot.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <set>
#include <thread>

#include "tests/session/test_scenes.h"

namespace viscera::session {
namespace {

TEST(SnapshotExchange, ReadersKeepTheirSnapshotWhileNewerOnesArePublished) {
  const auto model = testing::SmallModel(1);
  mechanics::State state = mechanics::InitialState(*model);
  SnapshotExchange exchange;
  EXPECT_EQ(exchange.Latest(), nullptr);
  state.steps = 1;
  exchange.Publish(state);
  const std::shared_ptr<const Snapshot> held = exchange.Latest();
  ASSERT_NE(held, nullptr);
  for (int k = 2; k < 10; ++k) {
    state.steps = k;
    state.q(0, 0) = k;
    exchange.Publish(state);
  }
  EXPECT_EQ(held->step, 1);  // immutable: never written after it was handed out
  EXPECT_EQ(held->q(0, 0), model->params().initial_q(0, 0));
  EXPECT_EQ(exchange.Latest()->step, 9);
  EXPECT_EQ(exchange.Latest()->q(0, 0), 9.0);
  EXPECT_EQ(exchange.Latest()->tools.size(), 1u);
}

// The render thread holds one snapshot while the mechanics thread publishes every step:
// three buffers serve it all, so the mechanics thread never allocates.
TEST(SnapshotExchange, OneReaderHoldingASnapshotLeavesThreeBuffersInUse) {
  const auto model = testing::SmallModel(1);
  mechanics::State state = mechanics::InitialState(*model);
  SnapshotExchange exchange;
  std::set<const Snapshot*> buffers;
  std::shared_ptr<const Snapshot> held;
  for (int k = 0; k < 200; ++k) {
    state.steps = k;
    exchange.Publish(state);
    buffers.insert(exchange.Latest().get());
    if (k % 7 == 0) held = exchange.Latest();  // the reader takes a new one now and then
    EXPECT_EQ(held->step, k - k % 7);          // and what it holds never changes
  }
  EXPECT_EQ(buffers.size(), 3u);
}

TEST(SnapshotExchange, AReaderThreadSeesWholeSnapshotsInOrder) {
  const auto model = testing::SmallModel(0);
  mechanics::State state = mechanics::InitialState(*model);
  SnapshotExchange exchange;
  std::atomic<bool> done{false};
  std::atomic<int> torn{0}, backwards{0}, seen{0};
  std::thread reader([&] {
    int64_t last = -1;
    while (!done.load()) {
      const auto s = exchange.Latest();
      if (s == nullptr) continue;
      // every row of a snapshot was written with its step number: a torn one would mix
      if ((s->q.array() != static_cast<double>(s->step)).any()) ++torn;
      if (s->step < last) ++backwards;
      last = s->step;
      ++seen;
    }
  });
  // publish until the reader has looked many times (it may start late), at least 20000 times
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (int k = 0; k < 20000 || (seen.load() < 1000 && std::chrono::steady_clock::now() < give_up);
       ++k) {
    state.steps = k;
    state.q.setConstant(k);
    exchange.Publish(state);
  }
  done = true;
  reader.join();
  EXPECT_EQ(torn.load(), 0);
  EXPECT_EQ(backwards.load(), 0);
  EXPECT_GE(seen.load(), 1000);
}

}  // namespace
}  // namespace viscera::session
