#include "haptic/local_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

#include "common/check.h"

namespace viscera::haptic {
namespace {

constexpr int64_t kMs = 1'000'000;

// A spring holding the tool at `anchor` (a grasp: it pushes and pulls), F = k (anchor - x).
Answer SpringAnswer(int64_t seq, const Vec3& x_answered, const Vec3& anchor, double k) {
  Answer a;
  a.seq = seq;
  a.step = seq;
  a.pose_seq = seq;
  a.force = k * (anchor - x_answered);
  a.stiffness = k * Mat3::Identity();
  a.grasping = true;
  return a;
}

TEST(RestoringStiffness, SymmetricWithEigenvaluesClippedToTheCap) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 300.0);
  for (int trial = 0; trial < 500; ++trial) {
    Mat3 k;
    for (int i = 0; i < 9; ++i) k(i / 3, i % 3) = n(rng);
    bool clipped = false;
    const Mat3 r = RestoringStiffness(k, 400.0, &clipped);
    EXPECT_LT((r - r.transpose()).norm(), 1e-9);
    Eigen::SelfAdjointEigenSolver<Mat3> eig(r);
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9);
    EXPECT_LE(eig.eigenvalues().maxCoeff(), 400.0 + 1e-9);
    Eigen::SelfAdjointEigenSolver<Mat3> sent(0.5 * (k + k.transpose()));
    const bool outside =
        sent.eigenvalues().minCoeff() < 0.0 || sent.eigenvalues().maxCoeff() > 400.0;
    EXPECT_EQ(clipped, outside);
    // within the range it changes nothing but the antisymmetric part
    if (!outside) {
      EXPECT_LT((r - 0.5 * (k + k.transpose())).norm(), 1e-9);
    }
  }
}

TEST(RestoringStiffness, NegativeStiffnessNeverReachesTheDevice) {
  bool clipped = false;
  const Mat3 r = RestoringStiffness(Vec3(-200, 50, 3000).asDiagonal(), 800.0, &clipped);
  EXPECT_TRUE(clipped);
  EXPECT_NEAR(r(0, 0), 0.0, 1e-9);
  EXPECT_NEAR(r(1, 1), 50.0, 1e-9);
  EXPECT_NEAR(r(2, 2), 800.0, 1e-9);
}

TEST(ColgateBound, IsTwiceTheDampingOverThePeriod) {
  EXPECT_DOUBLE_EQ(ColgateStiffnessBound(0.5, 1e-3), 1000.0);
}

// A linear spring (a grasp) answered at 100 Hz with 10 ms of delay: the local model gives the exact
// spring force at every 1 ms sample; the newest answer's force held (zero-order hold) does not.
TEST(LocalModel, RendersALinearSpringExactlyBetweenDelayedAnswers) {
  LocalModel model(
      {.max_stiffness_n_m = 1000.0, .crossfade_periods = 1, .stale_after_s = 1.0, .fade_s = 1e-3});
  const Vec3 wall(0.001, 0, 0.0);
  const double k = 200.0;
  std::vector<Vec3> sent;  // positions by pose seq (one per ms)
  double worst_model = 0.0, worst_hold = 0.0;
  for (int ms = 0; ms < 400; ++ms) {
    const int64_t now = (ms + 1) * kMs;
    const Vec3 x(0, 0.002 * std::cos(ms * 1e-3 * 2 * M_PI),
                 -0.01 * std::sin(ms * 1e-3 * 2 * M_PI * 2.0));
    sent.push_back(x);
    // every 10 ms the server answers the pose sent 10 ms earlier
    if (ms >= 10 && ms % 10 == 0) {
      const int64_t seq = ms - 10;
      model.Offer(SpringAnswer(seq, sent[static_cast<size_t>(seq)], wall, k),
                  sent[static_cast<size_t>(seq)], (seq + 1) * kMs, now);
    }
    const Vec3 f = model.Force(x, now);
    if (ms < 20) continue;
    const Vec3 exact = k * (wall - x);
    worst_model = std::max(worst_model, (f - exact).norm());
    worst_hold = std::max(worst_hold, (model.newest().force - exact).norm());
  }
  EXPECT_LT(worst_model, 1e-9);
  EXPECT_GT(worst_hold, 0.1);  // the delay matters: a zero-order hold is far off
}

TEST(LocalModel, CrossFadesANewAnswerLinearlyInTime) {
  LocalModel model({.max_stiffness_n_m = 1000.0,
                    .crossfade_periods = 5,
                    .max_crossfade_s = 0.005,
                    .stale_after_s = 1.0,
                    .fade_s = 1e-3});
  const Vec3 x = Vec3::Zero();
  Answer a;
  a.seq = 0;
  a.pose_seq = 0;
  a.force = Vec3(0, 0, 1.0);
  model.Offer(a, x, 0, kMs);
  for (int i = 0; i < 10; ++i) model.Force(x, (i + 2) * kMs);  // settled on 1 N, gain 1
  a.seq = 1;
  a.pose_seq = 1;
  a.force = Vec3(0, 0, 2.0);
  model.Offer(a, x, 11 * kMs, 12 * kMs);
  for (int i = 1; i <= 7; ++i) {
    const double fz = model.Force(x, (12 + i) * kMs).z();
    EXPECT_NEAR(fz, 1.0 + std::min(1.0, i / 5.0), 1e-12) << "period " << i;
  }
}

TEST(LocalModel, DropsStaleAndOutOfOrderAnswersAndCountsThem) {
  LocalModel model({});
  Answer a;
  a.seq = 10;
  a.pose_seq = 5;
  a.force = Vec3(1, 0, 0);
  EXPECT_EQ(model.Offer(a, Vec3::Zero(), 0, kMs), LocalModel::Intake::kAccepted);
  Answer older = a;
  older.seq = 9;  // an older server message
  older.pose_seq = 6;
  EXPECT_EQ(model.Offer(older, Vec3::Zero(), 0, kMs), LocalModel::Intake::kOutOfOrder);
  Answer older_pose = a;
  older_pose.seq = 11;  // newer message, but it answers an older pose
  older_pose.pose_seq = 4;
  EXPECT_EQ(model.Offer(older_pose, Vec3::Zero(), 0, kMs), LocalModel::Intake::kOutOfOrder);
  Answer same = a;  // a duplicate
  EXPECT_EQ(model.Offer(same, Vec3::Zero(), 0, kMs), LocalModel::Intake::kOutOfOrder);
  EXPECT_EQ(model.out_of_order(), 3);
  EXPECT_EQ(model.accepted(), 1);
  EXPECT_EQ(model.newest().force, Vec3(1, 0, 0));
}

TEST(LocalModel, FadesSmoothlyToZeroWhenStaleAndBackWhenAnswersReturn) {
  const double stale = 0.05, fade = 0.1;
  LocalModel model({.max_stiffness_n_m = 1000.0,
                    .crossfade_periods = 1,
                    .stale_after_s = stale,
                    .fade_s = fade});
  Answer a;
  a.seq = 0;
  a.pose_seq = 0;
  a.force = Vec3(0, 0, 2.0);
  model.Offer(a, Vec3::Zero(), 0, kMs);
  double prev = 0.0, largest_step = 0.0;
  int64_t zero_at = -1;
  for (int ms = 1; ms <= 400; ++ms) {
    if (ms >= 300 && ms % 10 == 0) {  // answers come back, every 10 ms
      ++a.seq;
      ++a.pose_seq;
      model.Offer(a, Vec3::Zero(), ms * kMs, ms * kMs);
    }
    const double f = model.Force(Vec3::Zero(), ms * kMs).z();
    if (ms > 1) largest_step = std::max(largest_step, std::abs(f - prev));
    if (zero_at < 0 && ms > 100 && f == 0.0) zero_at = ms;
    prev = f;
  }
  EXPECT_EQ(model.fade_events(), 1);
  // zero once the model is stale_after + fade old, no earlier than stale_after
  EXPECT_GE(zero_at, 50);
  EXPECT_LE(zero_at, 151);
  // the raised cosine's steepest slope is pi/2 F / fade; the fade-in rises at F / fade
  EXPECT_LE(largest_step, M_PI / 2 * 2.0 / fade * 1e-3 + 1e-9);
  EXPECT_NEAR(prev, 2.0, 1e-12);  // back to full force 100 ms after the answers returned
}

TEST(LocalModel, ANonFiniteAnswerGivesZeroForceACountAndDoesNotBlockLaterAnswers) {
  LocalModel model(
      {.crossfade_periods = 1, .stale_after_s = 1.0, .fade_s = 0.01, .nonfinite_hold_s = 0.02});
  Answer a;
  a.seq = 0;
  a.pose_seq = 0;
  a.force = Vec3(0, 0, 1.0);
  model.Offer(a, Vec3::Zero(), 0, kMs);
  for (int ms = 2; ms < 30; ++ms) model.Force(Vec3::Zero(), ms * kMs);
  EXPECT_NEAR(model.Force(Vec3::Zero(), 30 * kMs).z(), 1.0, 1e-12);
  for (const double bad : {std::nan(""), double{INFINITY}, -double{INFINITY}}) {
    Answer nan = a;
    nan.seq = 1'000'000;  // even a far-ahead sequence number must not block good answers
    nan.pose_seq = 1'000'000;
    nan.stiffness(1, 2) = bad;
    EXPECT_EQ(model.Offer(nan, Vec3::Zero(), 30 * kMs, 31 * kMs), LocalModel::Intake::kNonFinite);
  }
  EXPECT_EQ(model.nonfinite(), 3);
  EXPECT_EQ(model.Force(Vec3::Zero(), 32 * kMs), Vec3::Zero());
  a.seq = 1;
  a.pose_seq = 1;
  EXPECT_EQ(model.Offer(a, Vec3::Zero(), 40 * kMs, 40 * kMs), LocalModel::Intake::kAccepted);
  EXPECT_EQ(model.Force(Vec3::Zero(), 45 * kMs), Vec3::Zero());  // still held at zero
  for (int ms = 46; ms < 70; ++ms) model.Force(Vec3::Zero(), ms * kMs);
  EXPECT_NEAR(model.Force(Vec3::Zero(), 70 * kMs).z(), 1.0, 1e-12);
}

TEST(LocalModel, ContactExtrapolationNeverPullsButAGraspDoes) {
  LocalModel model(
      {.crossfade_periods = 1, .max_crossfade_s = 0.0, .stale_after_s = 1.0, .fade_s = 1e-3});
  Answer a;
  a.seq = 0;
  a.pose_seq = 0;
  a.force = Vec3(0, 0, 1.0);  // 1 N up at z = 0 with 100 N/m: zero at z = 1 cm
  a.stiffness(2, 2) = 100.0;
  model.Offer(a, Vec3::Zero(), 0, 0);
  model.Force(Vec3::Zero(), kMs);
  EXPECT_NEAR(model.Force(Vec3(0, 0, 0.005), 2 * kMs).z(), 0.5, 1e-12);
  EXPECT_NEAR(model.Force(Vec3(0, 0, 0.03), 3 * kMs).z(), 0.0, 1e-12);  // lifted off: no pull
  a.seq = 1;
  a.pose_seq = 1;
  a.grasping = true;  // holding the tube: it pulls back
  model.Offer(a, Vec3::Zero(), 3 * kMs, 3 * kMs);
  EXPECT_NEAR(model.Force(Vec3(0, 0, 0.03), 4 * kMs).z(), -2.0, 1e-12);
}

TEST(LocalModel, TheCrossFadeLastsAboutTheIntervalBetweenAnswersWithinItsBounds) {
  for (const double interval_ms : {1.0, 10.0, 100.0}) {
    LocalModel model({.period_s = 1e-3, .crossfade_periods = 4, .max_crossfade_s = 0.025});
    Answer a;
    for (int k = 0; k < 50; ++k) {
      a.seq = a.pose_seq = k;
      model.Offer(a, Vec3::Zero(), 0, static_cast<int64_t>(k * interval_ms * kMs));
    }
    EXPECT_NEAR(model.crossfade_s(), std::clamp(interval_ms * 1e-3, 0.004, 0.025), 1e-9)
        << interval_ms;
  }
}

// The server's answers can change direction from one step to the next (a contact that pushes,
// then a speculative one that pulls): the one-sided rule of each answer must not make the
// rendered force jump when the newest answer's direction flips.
TEST(LocalModel, AnAnswerFlippingDirectionIsCrossFadedNotSwitched) {
  LocalModel model({.max_stiffness_n_m = 1000.0,
                    .period_s = 1e-3,
                    .crossfade_periods = 4,
                    .max_crossfade_s = 0.004,
                    .stale_after_s = 1.0,
                    .fade_s = 1e-3});
  Answer up;
  up.seq = up.pose_seq = 0;
  up.force = Vec3(0, 0, 0.2);
  up.stiffness(2, 2) = 100.0;
  model.Offer(up, Vec3::Zero(), 0, 0);
  Vec3 prev = Vec3::Zero();
  double largest = 0.0;
  for (int ms = 1; ms <= 30; ++ms) {
    if (ms == 10) {
      Answer down;
      down.seq = down.pose_seq = 1;
      down.force = Vec3(0, 0, -0.08);
      model.Offer(down, Vec3::Zero(), ms * kMs, ms * kMs);
    }
    const Vec3 f = model.Force(Vec3::Zero(), ms * kMs);
    if (ms > 3) largest = std::max(largest, (f - prev).norm());
    prev = f;
  }
  EXPECT_NEAR(prev.z(), -0.08, 1e-12);
  EXPECT_LE(largest, 0.28 / 4 + 1e-12);  // the whole change spread over the 4 ms fade
}

TEST(LocalModel, RejectsBadOptions) {
  EXPECT_THROW(LocalModel({.max_stiffness_n_m = 0.0}), InputError);
  EXPECT_THROW(LocalModel({.crossfade_periods = 0}), InputError);
  EXPECT_THROW(LocalModel({.fade_s = 0.0}), InputError);
}

}  // namespace
}  // namespace viscera::haptic
