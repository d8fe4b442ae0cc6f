#include "collision/verlet_list.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace viscera::collision {

VerletList::VerletList(ContactDetector detector, double skin) : detector_(detector), skin_(skin) {
  ThrowUnless(skin > 0.0, "Verlet list skin ", skin, " m: must be > 0");
}

void VerletList::MeasureTravel(const std::vector<Sphere>& spheres,
                               const std::vector<ToolCapsule>& tools) {
  travel_.resize(spheres.size() + tools.size());
  for (size_t i = 0; i < spheres.size(); ++i)
    travel_[i] = (spheres[i].centre - centres_at_search_[i]).norm();
  for (size_t t = 0; t < tools.size(); ++t) {
    travel_[spheres.size() + t] =
        std::sqrt(std::max((tools[t].tip - tools_at_search_[t].tip).squaredNorm(),
                           (tools[t].port - tools_at_search_[t].port).squaredNorm()));
  }
}

bool VerletList::Update(const std::vector<Sphere>& spheres, const std::vector<Obstacle>& obstacles,
                        const std::vector<ToolCapsule>& tools, double margin) {
  bool same_bodies = valid_ && spheres.size() == centres_at_search_.size() &&
                     tools.size() == tools_at_search_.size();
  for (size_t t = 0; same_bodies && t < tools.size(); ++t) {
    same_bodies = tools[t].present == tools_at_search_[t].present &&
                  tools[t].radius == tools_at_search_[t].radius;
  }
  if (same_bodies) {
    // A pair left out had a gap of at least searched_margin_ when it was last looked at (when
    // the later of its two bodies was searched). Since then that body moved by its travel and
    // the other by at most its travel plus what it had moved when a partial search left it
    // (drift_): distances are 1-Lipschitz in each body's displacement. So its gap now is at
    // least searched_margin_ - drift_ - 2 x the largest travel.
    MeasureTravel(spheres, tools);
    const double worst = travel_.empty() ? 0.0 : *std::max_element(travel_.begin(), travel_.end());
    const double spare = searched_margin_ - drift_ - margin;
    if (2.0 * worst <= spare) return false;
    // Bodies beyond a third of the spare margin are searched again; the others then keep the
    // bound: 2 x spare/3 of travel plus spare/3 of drift.
    if (spare > kLeastPartialSpare * skin_ && SearchMoved(spheres, obstacles, tools, spare / 3.0))
      return true;
  }

  searched_margin_ = margin + skin_;
  drift_ = 0.0;
  detector_.Detect(spheres, obstacles, tools, &candidates_, searched_margin_);
  // The partial searches filter the list into kept_ and swap the two: both keep the list's
  // high-water capacity, so that the first partial search, long after the buffers were sized,
  // allocates nothing.
  kept_.reserve(candidates_.capacity());
  centres_at_search_.resize(spheres.size());
  for (size_t i = 0; i < spheres.size(); ++i) centres_at_search_[i] = spheres[i].centre;
  tools_at_search_ = tools;  // same size after the first search: no allocation
  valid_ = true;
  ++searches_;
  return true;
}

bool VerletList::SearchMoved(const std::vector<Sphere>& spheres,
                             const std::vector<Obstacle>& obstacles,
                             const std::vector<ToolCapsule>& tools, double threshold) {
  const size_t n = spheres.size();
  moved_spheres_.resize(n);
  moved_tools_.resize(tools.size());
  size_t moved = 0;
  double left = 0.0;  // the largest travel of a body not searched again
  for (size_t k = 0; k < travel_.size(); ++k) {
    const bool far = travel_[k] > threshold;
    if (k < n) {
      moved_spheres_[k] = far;
      moved += far;
    } else {
      moved_tools_[k - n] = far;
    }
    if (!far) left = std::max(left, travel_[k]);
  }
  // Most of the pile moved (a fall): one whole search costs less than many partial ones.
  if (moved > n / kPartialShare) return false;

  kept_.clear();
  for (const ContactCandidate& c : candidates_) {
    const bool involved = moved_spheres_[c.a] ||
                          (c.kind == ContactKind::kSelf && moved_spheres_[c.b]) ||
                          (c.kind == ContactKind::kTool && moved_tools_[c.b]);
    if (!involved) kept_.push_back(c);
  }
  candidates_.swap(kept_);
  detector_.DetectAround(spheres, obstacles, tools, moved_spheres_, moved_tools_, &candidates_,
                         searched_margin_);
  for (size_t i = 0; i < n; ++i) {
    if (moved_spheres_[i]) centres_at_search_[i] = spheres[i].centre;
  }
  for (size_t t = 0; t < tools.size(); ++t) {
    if (moved_tools_[t]) tools_at_search_[t] = tools[t];
  }
  drift_ = std::max(drift_, left);
  ++partial_searches_;
  return true;
}

}  // namespace viscera::collision
