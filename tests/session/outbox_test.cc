#include "session/outbox.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>
#include <vector>

namespace viscera::session {
namespace {

using viscera_proto::force_feedback_t;
using viscera_proto::session_status_t;
using viscera_proto::skeleton_state_t;

force_feedback_t Force(int64_t step) {
  force_feedback_t f{};
  f.step = step;
  return f;
}

session_status_t Status(int64_t steps) {
  session_status_t s{};
  s.steps = steps;
  return s;
}

// A full queue loses its oldest force first (a newer one supersedes it), never a status while
// a force is there; with no force queued, the oldest message. The size never passes the bound.
TEST(Outbox, AFullQueueDropsTheOldestForceFirst) {
  std::deque<Outbox::Item> queue;
  EXPECT_FALSE(Outbox::PushBounded(&queue, Status(0), 3));
  EXPECT_FALSE(Outbox::PushBounded(&queue, Force(1), 3));
  EXPECT_FALSE(Outbox::PushBounded(&queue, Force(2), 3));
  EXPECT_TRUE(Outbox::PushBounded(&queue, Force(3), 3));  // drops force 1, keeps the status
  ASSERT_EQ(queue.size(), 3u);
  EXPECT_EQ(std::get<session_status_t>(queue[0]).steps, 0);
  EXPECT_EQ(std::get<force_feedback_t>(queue[1]).step, 2);
  EXPECT_EQ(std::get<force_feedback_t>(queue[2]).step, 3);
  queue.clear();
  for (int i = 0; i < 3; ++i) Outbox::PushBounded(&queue, Status(i), 3);
  EXPECT_TRUE(Outbox::PushBounded(&queue, Status(3), 3));  // no force: the oldest goes
  EXPECT_EQ(std::get<session_status_t>(queue.front()).steps, 1);
  EXPECT_EQ(queue.size(), 3u);
}

// The last check before the wire: a force or skeleton with a NaN or an infinity is counted and
// never published; a finite one is. (Without the AllFinite check in Outbox::PushItem the
// subscriber sees the NaN force and this test fails.)
TEST(Outbox, ANonFiniteForceOrSkeletonIsNeverSent) {
  bus::LcmBus bus("memq://");
  std::vector<force_feedback_t> forces;
  int skeletons = 0;
  bus.Subscribe<force_feedback_t>("F",
                                  [&](const force_feedback_t& f, int64_t) { forces.push_back(f); });
  bus.Subscribe<skeleton_state_t>("K", [&](const skeleton_state_t&, int64_t) { ++skeletons; });
  {
    Outbox outbox(&bus, nullptr, {"F", "K", "S", "R"}, 0);
    force_feedback_t nan = Force(1);
    nan.force[1] = std::numeric_limits<double>::quiet_NaN();
    force_feedback_t inf = Force(2);
    inf.stiffness[2][2] = std::numeric_limits<double>::infinity();
    skeleton_state_t k{};
    k.num_points = 1;
    k.points = {{0.0, std::numeric_limits<double>::infinity(), 0.0}};
    outbox.Push(nan);
    outbox.Push(inf);
    outbox.Push(k);
    outbox.Push(Force(3));
    outbox.Flush();
    outbox.Drain();
    EXPECT_EQ(outbox.nonfinite(), 3);
    EXPECT_EQ(outbox.dropped(), 0);
  }
  bus.Drain();
  ASSERT_EQ(forces.size(), 1u);
  EXPECT_EQ(forces[0].step, 3);
  EXPECT_EQ(skeletons, 0);
}

}  // namespace
}  // namespace viscera::session
