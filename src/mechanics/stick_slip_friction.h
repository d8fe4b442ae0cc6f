#pragma once
/// Coulomb friction with a static phase for the implicit step (docs/friction.md). Each contact
/// that friction holds keeps an anchor across sub-steps: the stretch of a tangential spring from
/// where it stuck, and whether it slid. Stuck, a contact is a spring and damper in its tangent
/// plane, linearized exactly, so a loop on a slope below atan mu holds still; sliding, it is a
/// constant force at the cone against its motion. Its own class because it alone carries state
/// from one sub-step to the next (the anchors, found in O(1) by a bucket index) and within one
/// (the pairs it held, which a solve may revise), which neither the contact law nor the geometry
/// has.
#include <cstdint>
#include <vector>

#include "collision/contact_detector.h"
#include "collision/sphere_chain.h"
#include "mechanics/contact_law.h"
#include "mechanics/contact_window.h"
#include "mechanics/model_params.h"
#include "mechanics/state.h"

namespace viscera::mechanics {

class StickSlipFriction {
 public:
  /// @pre cp and chain outlive this; sphere_mass (kg) is one sphere's share of the tube's.
  StickSlipFriction(const ContactParams& cp, const collision::SphereChain& chain,
                    double sphere_mass);

  /// m/s: a slower reversal is left to the next sub-step, which starts it stuck (its energy,
  /// m v^2 / 2, is about 1e-9 J for a 10 g contact).
  static constexpr double kReversal = 5e-4;
  /// A reversal is solved again only where the sliding force held constant differs from the
  /// stuck spring's by more than this share of the cone (k_t h u): closer, the constant force is
  /// the spring's at the cone, and the energy it gives, k_t (h u)^2 / 2, the spring's stretch
  /// takes back in Advance.
  static constexpr double kReversalShare = 0.25;
  /// A stuck contact whose spring and damper end the sub-step beyond this many times the cone
  /// slides in the next solve of the same sub-step (closer to the cone, it slides from the next
  /// sub-step on: a resting pile has many contacts at the cone's edge).
  static constexpr double kOverload = 2.0;
  /// m/s: the speed the force a stuck pair held beyond the cone must give its spheres within the
  /// sub-step for the pair to be solved again as sliding. Slower, the one sub-step it was held
  /// moved them by micrometres (25 µm at 100 Hz), and it slides from the next one on.
  static constexpr double kOverloadSpeed = 5e-3;
  /// A stuck contact's tangential spring, as a share of the normal stiffness (unless the scene
  /// sets contacts.tangential_stiffness): stiff enough that a contact moves only micrometres
  /// before it slides (mu f_n / k_t), soft enough that a stuck pair turning within a 10 ms
  /// sub-step does not push itself deeper (at the normal stiffness, a jammed pile held by the
  /// limiter alone gained 7 mJ in one 100 Hz step; docs/friction.md).
  static constexpr double kTangentialShare = 0.2;
  /// The key a pair's anchor is found by: its kind and its two sides' indices.
  static uint64_t Key(collision::ContactKind kind, int a, int b) {
    return (static_cast<uint64_t>(kind) << 42) | (static_cast<uint64_t>(a) << 21) |
           static_cast<uint64_t>(b);
  }

  /// The next force evaluations of a sub-step of length h start from `anchors` (nullptr: the
  /// regularized law, and Add is not called). The anchors must outlive those evaluations.
  void Use(const std::vector<FrictionAnchor>* anchors, double h);
  bool active() const { return anchors_ != nullptr; }
  /// A force evaluation starts: no pair held yet.
  void ClearPairs() {
    pairs_.clear();
    hint_ = 0;
  }
  /// A sub-step starts: every contact sticks or slides as its anchor has it.
  void ClearRevisions() {
    stuck_.clear();
    slid_.clear();
  }
  /// On an active pair with Coulomb coefficient mu (ContactLaw::Evaluate's, with stick_slip):
  /// adds its tangential force to p->force, its stiffness to *k and its damping to *d, and keeps
  /// the pair for Revise and Advance.
  void Add(const collision::ContactCandidate& c, double mu, ContactPenalty* p, Mat3* k, Mat3* d);
  /// After a solve whose end velocities are v + dv (#N by 3, dv's 3N values) and, for the tips,
  /// tool_velocity plus tip_dv (3 per tool; nullptr: none): a sliding contact that the friction
  /// turned back (faster than kReversal, kReversalShare) sticks in the next solve of the same
  /// sub-step (a constant force that overshoots would do work: energy from nothing), and a stuck
  /// one held far beyond the cone (kOverload, kOverloadSpeed) slides. Says whether any changed.
  bool Revise(const Points& v, const double* dv, const double* tip_dv,
              const std::vector<Vec3>& tool_velocity);
  /// A pair whose stick or slip a revision changed since the last force evaluation, as the change
  /// of what it adds: on its relative motion (side a's window less side b's for a self pair, side
  /// a's alone for an environment pair), stiffness `k` and damping `d` (its tangent plane's k_t
  /// and c, either sign), and on side a the force `force` (side b takes its opposite).
  struct Change {
    collision::ContactKind kind = collision::ContactKind::kSelf;
    ContactWindow a, b;
    Mat3 k = Mat3::Zero(), d = Mat3::Zero();
    Vec3 force = Vec3::Zero();
    /// J x, the pair's relative motion in x (3N values: a velocity, a motion).
    Vec3 Motion(const double* x) const {
      Vec3 r = a.Gather(x);
      if (kind == collision::ContactKind::kSelf) r -= b.Gather(x);
      return r;
    }
    /// y += J' f: the pair's force f on each side.
    void Scatter(const Vec3& f, double* y) const {
      a.Scatter(f, y);
      if (kind == collision::ContactKind::kSelf) b.Scatter(-f, y);
    }
  };
  /// After Revise: every pair held in the last evaluation sticks or slides as the next evaluation
  /// of the same sub-step would make it (its force, stiffness and damping being the only parts of
  /// that evaluation to change), and *changes gets those that differ from the evaluation. Returns
  /// false, changing nothing, when a tool's pair would change (its tip's rows change too: the
  /// sub-step is evaluated again).
  bool ApplyRevisions(std::vector<Change>* changes);
  /// Once a sub-step is accepted: each pair held in the last evaluation moves its anchor by the
  /// contact's tangential motion over the sub-step (dq, #N by 3; a tool's tip moved by h times
  /// its new velocity), capped by the cone, and is marked sliding or stuck as the sub-step ended
  /// it; the other anchors are dropped. Replaces state->friction.
  void Advance(const Points& dq, double h, State* state);
  /// J: the tangential springs' energy as the last accepted sub-step left them.
  double energy() const { return energy_; }

 private:
  struct Pair {
    uint64_t key = 0;
    collision::ContactKind kind = collision::ContactKind::kSelf;
    int tool = 0;
    int a = 0, b = -1;  // spheres; b: a self pair's other side
    ShaftLever lever;   // a tool pair's
    Vec3 normal = Vec3::Zero();
    Vec3 stretch = Vec3::Zero();  // at the sub-step's start, in its tangent plane
    Vec3 slip = Vec3::Zero();     // the tangential relative velocity at the start
    double limit = 0.0;           // N: mu f_n, f_n at the sub-step's start (lagged)
    bool stuck = false;
    bool evaluated_stuck = false;   // as the evaluation added it
    bool held = false;              // it sticks unless a revision made it slide (Add's trial)
    Vec3 direction = Vec3::Zero();  // sliding: the way the contact moves (friction opposes it)
  };
  // The anchor of `key`, or nullptr. The anchors are in the order of the last evaluation's
  // pairs, which the next evaluation meets in the same order but for the pairs that came or
  // went: the one after the last found is tried first, the bucket index (made on the first miss
  // after Use) only when it is not the one.
  const FrictionAnchor* Find(uint64_t key);
  void IndexAnchors();
  // Whether a pair sticks: as its trial has it (held), unless Revise made it slide or stick.
  bool Sticks(uint64_t key, bool held) const;
  // A sliding pair's direction: its trial stretch's (the stretch moved by h v_t), or its slip's.
  Vec3 SlideDirection(const Vec3& stretch, const Vec3& slip) const;
  // moved_[k] <- sphere k's motion: its window's of x (#N by 3) plus dx (3N values, or nullptr).
  // Once per sphere rather than once per pair and side: the same sums, in the same order.
  void GatherSpheres(const Points& x, const double* dx);
  // A pair's tangential relative motion from moved_, less the lever rule's share of the tool's
  // `tip` for a tool pair.
  Vec3 Motion(const Pair& pair, const Vec3& tip) const;

  const ContactParams& cp_;
  const collision::SphereChain& chain_;
  double sphere_mass_;
  double tangential_stiffness_;
  // The anchors the sub-step starts from and its length (Use).
  const std::vector<FrictionAnchor>* anchors_ = nullptr;
  double h_ = 0.0;
  // The anchors by the pair's kind and first sphere (a counting sort, made at the first miss of the
  // hint): bucket kind * spheres + a holds order_[bucket_[i] .. bucket_[i + 1]), a few pairs each,
  // so that a contact finds its anchor in O(1) rather than by a search.
  std::vector<int> bucket_, cursor_, order_;
  bool indexed_ = false;
  size_t hint_ = 0;  // the anchor Find tries first
  double energy_ = 0.0;
  std::vector<Pair> pairs_;      // held in the last force evaluation
  std::vector<uint64_t> stuck_;  // pairs Revise made stick in this sub-step
  std::vector<uint64_t> slid_;   // ... and slide
  std::vector<FrictionAnchor> next_anchors_;
  std::vector<Vec3> moved_;  // per sphere (GatherSpheres)
};

}  // namespace viscera::mechanics
