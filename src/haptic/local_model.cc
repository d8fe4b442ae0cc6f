#include "haptic/local_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "common/check.h"

namespace viscera::haptic {

namespace {

bool Finite(const Answer& a) { return a.force.allFinite() && a.stiffness.allFinite(); }

}  // namespace

Mat3 RestoringStiffness(const Mat3& k_sent, double max_n_m, bool* clipped) {
  const Mat3 sym = 0.5 * (k_sent + k_sent.transpose());
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(sym);
  Vec3 lambda = eig.eigenvalues();
  const double tol = 1e-9 * std::max(1.0, max_n_m);
  *clipped = lambda.minCoeff() < -tol || lambda.maxCoeff() > max_n_m + tol;
  lambda = lambda.cwiseMax(0.0).cwiseMin(max_n_m);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

LocalModel::LocalModel(LocalModelOptions options) : options_(options) {
  ThrowUnless(options_.max_stiffness_n_m > 0.0, "local model: stiffness cap must be > 0 N/m, got ",
              options_.max_stiffness_n_m);
  ThrowUnless(
      options_.fade_s > 0.0 && options_.stale_after_s >= 0.0 && options_.nonfinite_hold_s >= 0.0,
      "local model: fade ", options_.fade_s, " s must be > 0, stale-after ", options_.stale_after_s,
      " s and hold ", options_.nonfinite_hold_s, " s >= 0");
  ThrowUnless(
      options_.crossfade_periods >= 1 && options_.period_s > 0.0 && options_.max_crossfade_s >= 0.0,
      "local model: cross-fade must be >= 1 period (got ", options_.crossfade_periods, ") of ",
      options_.period_s, " s > 0, at most ", options_.max_crossfade_s, " s >= 0");
  crossfade_ns_ = static_cast<int64_t>(options_.crossfade_periods * options_.period_s * 1e9);
}

LocalModel::Intake LocalModel::Offer(const Answer& answer, const Vec3& x_answered,
                                     int64_t pose_sent_ns, int64_t now_ns) {
  if (!Finite(answer) || !x_answered.allFinite()) {
    FlagNonFinite(now_ns);
    return Intake::kNonFinite;
  }
  // newest wins: an older server message, or one answering an older pose, is dropped
  if (has_answer_ && (answer.seq <= newest_seq_ || answer.pose_seq < newest_pose_seq_)) {
    ++out_of_order_;
    return Intake::kOutOfOrder;
  }
  bool clipped = false;
  Affine next;
  next.K = RestoringStiffness(answer.stiffness, options_.max_stiffness_n_m, &clipped);
  next.a = answer.force + next.K * x_answered;
  if (!answer.grasping && answer.force.norm() > 0.0) next.n = answer.force.normalized();
  if (clipped) ++stiffness_capped_;
  // the cross-fade lasts about the interval between answers (a running mean over ~10)
  if (has_answer_) {
    const auto interval = static_cast<double>(now_ns - to_since_ns_);
    interval_ns_ = interval_ns_ > 0.0 ? 0.9 * interval_ns_ + 0.1 * interval : interval;
    const double shortest = options_.crossfade_periods * options_.period_s * 1e9;
    crossfade_ns_ = static_cast<int64_t>(
        std::max(shortest, std::min(interval_ns_, options_.max_crossfade_s * 1e9)));
  }
  // what is rendered now is where the new answer's fade starts: frozen as a model with the
  // blended stiffness around the last position, one-sided along its own force
  Affine from;
  if (has_answer_) {
    const double alpha = Alpha(now_ns);
    const Vec3 f = Blend(last_x_, now_ns);
    from.K = (1.0 - alpha) * from_.K + alpha * to_.K;
    from.a = f + from.K * last_x_;
    if (!newest_.grasping && f.norm() > 0.0) from.n = f.normalized();
  }
  from_ = from;
  to_ = next;
  to_since_ns_ = now_ns;
  has_answer_ = true;
  newest_ = answer;
  newest_seq_ = answer.seq;
  newest_pose_seq_ = answer.pose_seq;
  newest_sent_ns_ = pose_sent_ns;
  ++accepted_;
  return Intake::kAccepted;
}

void LocalModel::FlagNonFinite(int64_t now_ns) {
  ++nonfinite_;
  gain_ = 0.0;
  hold_until_ns_ =
      std::max(hold_until_ns_, now_ns + static_cast<int64_t>(options_.nonfinite_hold_s * 1e9));
}

Vec3 LocalModel::Affine::Eval(const Vec3& x) const {
  Vec3 f = a - K * x;
  // one-sided contact: the extrapolation may relax the push to zero, never turn it into a pull
  const double along = f.dot(n);
  if (along < 0.0) f -= along * n;
  return f;
}

double LocalModel::Alpha(int64_t now_ns) const {
  return std::clamp(static_cast<double>(now_ns - to_since_ns_) / static_cast<double>(crossfade_ns_),
                    0.0, 1.0);
}

Vec3 LocalModel::Blend(const Vec3& x, int64_t now_ns) const {
  const double alpha = Alpha(now_ns);
  return (1.0 - alpha) * from_.Eval(x) + alpha * to_.Eval(x);
}

double LocalModel::age_s(int64_t now_ns) const {
  if (!has_answer_) return std::numeric_limits<double>::infinity();
  return static_cast<double>(now_ns - newest_sent_ns_) * 1e-9;
}

double LocalModel::TargetGain(int64_t now_ns) const {
  if (!has_answer_ || now_ns < hold_until_ns_) return 0.0;
  const double u = (age_s(now_ns) - options_.stale_after_s) / options_.fade_s;
  if (u <= 0.0) return 1.0;
  if (u >= 1.0) return 0.0;
  return 0.5 * (1.0 + std::cos(M_PI * u));  // raised cosine: no step in force or its slope
}

Vec3 LocalModel::Force(const Vec3& x_now, int64_t now_ns) {
  // gain: follows the staleness fade down, rises at most at 1 / fade per second
  const double target = TargetGain(now_ns);
  const bool stale = has_answer_ && age_s(now_ns) > options_.stale_after_s;
  if (stale && !fading_) ++fade_events_;
  fading_ = stale;
  const double dt = last_now_ns_ > 0 ? static_cast<double>(now_ns - last_now_ns_) * 1e-9 : 0.0;
  last_now_ns_ = now_ns;
  gain_ = std::min(target, gain_ + std::max(0.0, dt) / options_.fade_s);

  last_x_ = x_now;
  if (!has_answer_) return Vec3::Zero();
  return gain_ * Blend(x_now, now_ns);
}

}  // namespace viscera::haptic
