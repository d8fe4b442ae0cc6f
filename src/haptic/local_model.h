#pragma once
/// LocalModel: what the device renders between server answers. Each force_feedback_t gives the
/// force F_s on the hand at the pose x_a it answers and the local stiffness K_s the server
/// computed (a spring stiffness, positive where the tissue pushes back: F ~ F_s - K_s (x - x_a),
/// i.e. dF/dx = -K_s). Every device period the loop renders
///
///   F(x_now) = g(age) [ F_s - K (x_now - x_a) ]
///
/// - K: K_s symmetrized, its eigenvalues clipped to [0, max_stiffness]: restoring only (no
///   negative stiffness), never stiffer than the device holds or the sampled-spring passivity
///   bound allows (Colgate: K < 2 b / T);
/// - contact is one-sided: unless the tool grasps, the extrapolation never pulls the hand into
///   the tissue (each answer's force keeps a component >= 0 along its own F_s);
/// - successive answers are cross-faded: each answer is a model affine in x, F(x) = a - K x with
///   a = F_s + K x_a, and the force fades linearly in time from the old model's force to the new
///   one's. An answer arriving mid-fade starts from what was rendered then (frozen as a model
///   with the blended K around the last position), so nothing jumps when the answers' direction
///   flips (a contact that pushes, then one that pulls). The fade lasts the typical interval
///   between answers (at least crossfade_periods device periods, at most max_crossfade_s): what the
///   model could not predict (a tip slipping sideways) is spread over the time until the next
///   answer, a first-order hold, instead of arriving as a step at a 100 Hz session;
/// - stale or out-of-order answers (an older server sequence or answered pose) are dropped,
///   never replayed;
/// - g fades the force smoothly (raised cosine) to zero once the newest answer's pose is older
///   than stale_after, over fade; when answers come back g rises again at most at 1 / fade per
///   second, so neither way steps;
/// - an answer with a NaN or infinity anywhere is rejected and counted, and holds g at zero for
///   nonfinite_hold (the limiter ramps the force down meanwhile).
///
/// Threading: the device loop's thread only. Allocates nothing.
#include <cstdint>

#include "common/types.h"

namespace viscera::haptic {

/// One force_feedback_t of the rendered tool, as the loop hands it over.
struct Answer {
  int64_t seq = -1;               ///< header.seq (server's force messages, all tools)
  int64_t step = 0;               ///< mechanics step that produced it
  int64_t pose_seq = -1;          ///< the pose it answers
  Vec3 force = Vec3::Zero();      ///< N on the hand, world frame
  Mat3 stiffness = Mat3::Zero();  ///< N/m as sent (server's spring stiffness K_s)
  bool grasping = false;
};

struct LocalModelOptions {
  double max_stiffness_n_m = 800.0;  ///< cap on K's eigenvalues (N/m), > 0
  double period_s = 1e-3;            ///< the device loop's period (s), > 0
  int crossfade_periods = 4;         ///< shortest cross-fade, in device periods (>= 1)
  double max_crossfade_s = 0.025;    ///< longest cross-fade (s)
  double stale_after_s = 0.25;       ///< the fade starts when the model is this old (s)
  double fade_s = 0.15;              ///< fade length (s), > 0; also the fade-in rate
  double nonfinite_hold_s = 0.1;     ///< zero force this long after a non-finite answer (s)
};

class LocalModel {
 public:
  enum class Intake { kAccepted, kOutOfOrder, kNonFinite };

  /// @throws InputError for a non-positive stiffness cap or fade, crossfade_periods < 1.
  explicit LocalModel(LocalModelOptions options);

  /// Offers an answer whose pose was at `x_answered` (m) and was sent at `pose_sent_ns`
  /// (monotonic). `now_ns` is the loop's time. Non-finite answers are rejected before the
  /// order check, so an injected one cannot block later good answers.
  Intake Offer(const Answer& answer, const Vec3& x_answered, int64_t pose_sent_ns, int64_t now_ns);
  /// Counts a non-finite value met elsewhere (the device's reading): same hold as an answer.
  void FlagNonFinite(int64_t now_ns);

  /// The force to render at `x_now` (m) at `now_ns` (N). Zero before the first answer.
  Vec3 Force(const Vec3& x_now, int64_t now_ns);

  bool has_answer() const { return has_answer_; }
  /// Age of the newest answer's pose (s), +inf before the first answer.
  double age_s(int64_t now_ns) const;
  double gain() const { return gain_; }
  /// The cross-fade's length now (s): the typical interval between answers, within bounds.
  double crossfade_s() const { return static_cast<double>(crossfade_ns_) * 1e-9; }
  const Answer& newest() const { return newest_; }

  int64_t accepted() const { return accepted_; }
  int64_t out_of_order() const { return out_of_order_; }
  int64_t nonfinite() const { return nonfinite_; }
  int64_t stiffness_capped() const { return stiffness_capped_; }  ///< answers whose K was clipped
  int64_t fade_events() const { return fade_events_; }            ///< times a stale fade began

 private:
  struct Affine {  // F(x) = a - K x, one-sided along n (unit or zero) unless grasping
    Vec3 a = Vec3::Zero();
    Mat3 K = Mat3::Zero();
    Vec3 n = Vec3::Zero();
    Vec3 Eval(const Vec3& x) const;
  };
  double Alpha(int64_t now_ns) const;
  Vec3 Blend(const Vec3& x, int64_t now_ns) const;
  double TargetGain(int64_t now_ns) const;

  LocalModelOptions options_;
  Affine from_, to_;
  int64_t to_since_ns_ = 0;   // when `to_` arrived
  int64_t crossfade_ns_ = 0;  // current cross-fade length
  double interval_ns_ = 0.0;  // running mean of the interval between accepted answers
  bool has_answer_ = false;
  Answer newest_;
  int64_t newest_pose_seq_ = -1, newest_seq_ = -1;
  int64_t newest_sent_ns_ = 0;
  double gain_ = 0.0;
  bool fading_ = false;
  int64_t last_now_ns_ = 0;
  Vec3 last_x_ = Vec3::Zero();  // where the last Force was asked
  int64_t hold_until_ns_ = 0;
  int64_t accepted_ = 0, out_of_order_ = 0, nonfinite_ = 0, stiffness_capped_ = 0, fade_events_ = 0;
};

/// K_s symmetrized with eigenvalues clipped to [0, max]; *clipped says whether any was.
Mat3 RestoringStiffness(const Mat3& k_sent, double max_n_m, bool* clipped);

/// The stiffness a sampled spring of period `period_s` renders passively on a device of
/// physical damping `damping_n_s_m` (Colgate and Schenkel: b > K T / 2).
inline double ColgateStiffnessBound(double damping_n_s_m, double period_s) {
  return 2.0 * damping_n_s_m / period_s;
}

}  // namespace viscera::haptic
