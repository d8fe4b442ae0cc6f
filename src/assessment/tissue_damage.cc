#include "assessment/tissue_damage.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace viscera::assessment {

TissueDamage::TissueDamage(const mechanics::RunningParams& p, double length,
                           std::vector<std::string> tools)
    : p_(p), length_(length), names_(std::move(tools)), tools_(names_.size()) {
  // a last piece shorter than a tenth of a segment joins the one before
  const int n = std::max(1, static_cast<int>(std::floor(length / p.segment + 0.9)));
  dose_.assign(static_cast<size_t>(n), 0.0);
  flags_.assign(static_cast<size_t>(n), 0);
  events_.reserve(64);
}

int TissueDamage::SegmentOf(double s) const {
  const int k = static_cast<int>(std::floor(std::clamp(s, 0.0, 1.0) * length_ / p_.segment));
  return std::clamp(k, 0, segments() - 1);
}

double TissueDamage::max_dose() const {
  return dose_.empty() ? 0.0 : *std::max_element(dose_.begin(), dose_.end());
}

std::vector<std::pair<double, double>> TissueDamage::DamagedRanges() const {
  std::vector<std::pair<double, double>> ranges;
  for (int k = 0; k < segments(); ++k) {
    if (!flags_[static_cast<size_t>(k)]) continue;
    const double from = k * p_.segment / length_;
    const double to = std::min(1.0, (k + 1) * p_.segment / length_);
    if (!ranges.empty() && std::abs(ranges.back().second - from) < 1e-12) {
      ranges.back().second = to;
    } else {
      ranges.emplace_back(from, to);
    }
  }
  if (!ranges.empty() && segments() > 0 && flags_.back()) ranges.back().second = 1.0;
  return ranges;
}

void TissueDamage::Event(DamageKind kind, int segment, int tool, double t, double value) {
  static const char* kNames[] = {"", "pinch", "dose", "", "traction"};
  flags_[static_cast<size_t>(segment)] |= kind;
  events_.push_back({kNames[kind], segment, names_[static_cast<size_t>(tool)], t, value});
}

void TissueDamage::Add(int tool, bool grasping, double s, double grip, double pull, double t,
                       double dt) {
  Tool& k = tools_[static_cast<size_t>(tool)];
  if (!grasping) {
    k = Tool{};
    return;
  }
  const int segment = SegmentOf(s);
  max_grip_ = std::max(max_grip_, grip);
  max_traction_ = std::max(max_traction_, pull);
  // pinch: one event per grasp that squeezes past the perforation force
  if (grip > p_.pinch_force && !k.pinched) {
    k.pinched = true;
    Event(kPinch, segment, tool, t, grip);
  }
  // dose: grip x time on the held segment; one event when it first passes the damage dose
  double& dose = dose_[static_cast<size_t>(segment)];
  const bool below = dose <= p_.damage_dose;
  dose += grip * dt;
  if (below && dose > p_.damage_dose) Event(kDose, segment, tool, t, dose);
  // traction: one event per excursion of the pull past the breaking force
  if (pull > p_.traction_break) {
    if (!k.pulled) Event(kTraction, segment, tool, t, pull);
    k.pulled = true;
  } else {
    k.pulled = false;
  }
}

}  // namespace viscera::assessment
