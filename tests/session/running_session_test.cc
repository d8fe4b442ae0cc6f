// Running the bowel live: a session of scenes/bowel_run.toml whose left grasper takes the first
// part of the bowel with its jaws shut (the rough run's grasp, scripted) scores it as it steps,
// with the assessment's own RunningScore: its status carries the running figures and the pinch
// while it runs, its snapshots the damaged part for the frames, its final report the score.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <viscera_proto/session_status_t.hpp>

#include "assessment/status_report.h"
#include "bus/channels.h"
#include "scene/scene.h"
#include "tests/common/eventually.h"
#include "tests/session/script_driver.h"

namespace viscera::session {
namespace {

using viscera::testing::Eventually;
using viscera_proto::session_status_t;

constexpr int64_t kId = 7;

// The rough run's first grasp (scenes/bowel_run_rough.csv, the left grasper's rows to 2 s) with
// the jaws shut instead of closed to 0.2: 20 N of grip on segment 0, past the 10.3 N pinch force.
constexpr const char* kShutGrasp = R"(t,tool,x,y,z,qw,qx,qy,qz,jaw,aim
0,left,0.0294,-0.0444,0.1380,1,0,0,0,1,point
0.5,left,0.0294,-0.0444,0.1380,1,0,0,0,1,point
0.7,left,0.0294,-0.0444,0.1380,1,0,0,0,1,point
0.95,left,-0.0800,-0.1000,0.3000,1,0,0,0,1,tube@0.000000
1.15,left,-0.0800,-0.1000,0.3000,1,0,0,0,1,tube@0.002222
1.35,left,-0.0800,-0.1000,0.3000,1,0,0,0,1,tube@0.005556
1.55,left,0.0000,0.0000,0.0000,1,0,0,0,0,offset
2,left,0.0294,-0.0444,0.0580,1,0,0,0,0,point
)";

// scenes/bowel_run.toml as shipped: its 9 s settle is most of the test's time (about 12 s of
// one core; a shorter one leaves the coil falling, and its steps cost more than the session's
// period).
TEST(RunningSession, AShutGraspIsScoredLiveAndItsPinchIsInTheStatus) {
  const scene::Scene scene = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/bowel_run.toml");
  auto model = std::make_shared<const mechanics::Model>(scene.model);
  bus::LcmBus bus("memq://");
  std::vector<session_status_t> statuses;
  bus.Subscribe<session_status_t>(
      bus::SessionChannel(bus::kStatusPrefix, kId),
      [&](const session_status_t& s, int64_t) { statuses.push_back(s); });
  SessionConfig config;
  config.id = kId;
  config.server_id = "test";
  config.scene = "bowel_run";
  config.skeleton_rate_hz = 0.0;
  config.status_rate_hz = 10.0;
  config.snapshot_rate_hz = model->params().rate_hz;  // as while frames stream
  Session session(config, model, &bus, nullptr);
  testing::ScriptDriver driver(&session, script::ToolScript::Parse(kShutGrasp, "shut grasp"));
  session.Start();
  ASSERT_TRUE(Eventually([&] { return session.Status().sim_time >= 2.1; }, 60.0,
                         [&] {
                           driver.Post();
                           bus.Pump(2);
                         }));
  const std::shared_ptr<const Snapshot> snapshot = session.LatestSnapshot();
  session.Stop();
  bus.Drain();

  // the figures in the statuses while it ran: none hurt at first, then the pinch
  ASSERT_GE(statuses.size(), 10u);
  const session_status_t& first = statuses.front();
  EXPECT_EQ(first.running_segments, 90);
  EXPECT_EQ(first.running_num_missed, 90);
  EXPECT_EQ(first.running_num_events, 0);
  EXPECT_DOUBLE_EQ(first.running_pinch_force, 10.3);
  const auto pinched =
      std::find_if(statuses.begin(), statuses.end(),
                   [](const session_status_t& s) { return s.running_num_events > 0; });
  ASSERT_NE(pinched, statuses.end()) << "no damage event in any status";
  EXPECT_EQ(pinched->state, session_status_t::kRunning) << "seen live, not only at the end";
  EXPECT_EQ(pinched->running_event_kinds[0], "pinch");
  EXPECT_EQ(pinched->running_event_tools[0], "left");
  EXPECT_EQ(pinched->running_event_segments[0], 0);
  EXPECT_GT(pinched->running_event_values[0], 10.3);
  EXPECT_EQ(pinched->running_grasps, 1);
  EXPECT_EQ(pinched->running_damaged, std::vector<int32_t>{0});
  EXPECT_GT(pinched->running_coverage, 0.0);
  EXPECT_FALSE(pinched->running_passed);

  // the last status carries the final score: the assessment's own RunningReport, read back
  const session_status_t& last = statuses.back();
  ASSERT_EQ(last.state, session_status_t::kStopped);
  const assessment::Report report = session.Assessment();
  ASSERT_TRUE(report.has_running);
  const assessment::RunningReport& run = report.running;
  ASSERT_EQ(run.events.size(), 1u) << assessment::FormatRunning(run);
  EXPECT_EQ(run.events[0].kind, "pinch");
  EXPECT_EQ(run.grasps, 1);
  EXPECT_EQ(run.slips, 0);
  EXPECT_EQ(run.segments, 90);
  // no exposure watcher hands this session a camera (the server's does): the jaws inspect alone
  EXPECT_EQ(run.missed.size(), 89u) << "segment 0 was between the jaws";
  EXPECT_EQ(run.missed.front(), 1);
  EXPECT_DOUBLE_EQ(run.coverage, 1.0 / 90.0);
  EXPECT_GE(run.max_grip, 19.9);
  EXPECT_NE(std::find(run.failed.begin(), run.failed.end(), "damage"), run.failed.end());
  EXPECT_EQ(assessment::ReportFromStatus(last), report);

  // the frames' damaged part: segment 0, 5 cm of the 4.5 m
  ASSERT_NE(snapshot, nullptr);
  ASSERT_EQ(snapshot->damaged.size(), 1u);
  EXPECT_DOUBLE_EQ(snapshot->damaged[0].first, 0.0);
  EXPECT_DOUBLE_EQ(snapshot->damaged[0].second, 0.05 / 4.5);
}

}  // namespace
}  // namespace viscera::session
