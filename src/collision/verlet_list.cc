#include "collision/verlet_list.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "common/check.h"

namespace viscera::collision {

VerletList::VerletList(ContactDetector detector, double skin) : detector_(detector), skin_(skin) {
  ThrowUnless(skin > 0.0, "Verlet list skin ", skin, " m: must be > 0");
}

uint64_t VerletList::NextStamp() {
  static std::atomic<uint64_t> last{0};
  return last.fetch_add(1, std::memory_order_relaxed) + 1;
}

bool VerletList::Restore(const VerletMemory& memory) {
  if (memory.stamp == memory_.stamp) return false;
  memory_ = memory;  // vectors within their capacity: no allocation
  return true;
}

void VerletList::MeasureTravel(const std::vector<Sphere>& spheres,
                               const std::vector<ToolCapsule>& tools) {
  travel_.resize(spheres.size() + tools.size());
  for (size_t i = 0; i < spheres.size(); ++i)
    travel_[i] = (spheres[i].centre - memory_.centres_at_search[i]).norm();
  for (size_t t = 0; t < tools.size(); ++t) {
    travel_[spheres.size() + t] =
        std::sqrt(std::max((tools[t].tip - memory_.tools_at_search[t].tip).squaredNorm(),
                           (tools[t].port - memory_.tools_at_search[t].port).squaredNorm()));
  }
}

bool VerletList::Update(const std::vector<Sphere>& spheres, const std::vector<Obstacle>& obstacles,
                        const std::vector<ToolCapsule>& tools, double margin) {
  bool same_bodies = memory_.valid && spheres.size() == memory_.centres_at_search.size() &&
                     tools.size() == memory_.tools_at_search.size();
  for (size_t t = 0; same_bodies && t < tools.size(); ++t) {
    same_bodies = tools[t].present == memory_.tools_at_search[t].present &&
                  tools[t].radius == memory_.tools_at_search[t].radius;
  }
  if (same_bodies) {
    // A pair left out had a gap of at least searched_margin when it was last looked at (when
    // the later of its two bodies was searched). Since then that body moved by its travel and
    // the other by at most its travel plus what it had moved when a partial search left it
    // (drift): distances are 1-Lipschitz in each body's displacement. So its gap now is at
    // least searched_margin - drift - 2 x the largest travel.
    MeasureTravel(spheres, tools);
    const double worst = travel_.empty() ? 0.0 : *std::max_element(travel_.begin(), travel_.end());
    const double spare = memory_.searched_margin - memory_.drift - margin;
    if (2.0 * worst <= spare) return false;
    // Bodies beyond a third of the spare margin are searched again; the others then keep the
    // bound: 2 x spare/3 of travel plus spare/3 of drift.
    if (spare > kLeastPartialSpare * skin_ && SearchMoved(spheres, obstacles, tools, spare / 3.0))
      return true;
  }

  memory_.searched_margin = margin + skin_;
  memory_.drift = 0.0;
  detector_.Detect(spheres, obstacles, tools, &memory_.candidates, memory_.searched_margin);
  // The partial searches filter the list into kept_ and swap the two: both keep the list's
  // high-water capacity, so that the first partial search, long after the buffers were sized,
  // allocates nothing.
  kept_.reserve(memory_.candidates.capacity());
  memory_.centres_at_search.resize(spheres.size());
  for (size_t i = 0; i < spheres.size(); ++i) memory_.centres_at_search[i] = spheres[i].centre;
  memory_.tools_at_search = tools;  // same size after the first search: no allocation
  memory_.valid = true;
  memory_.stamp = NextStamp();
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
  for (const ContactCandidate& c : memory_.candidates) {
    const bool involved = moved_spheres_[c.a] ||
                          (c.kind == ContactKind::kSelf && moved_spheres_[c.b]) ||
                          (c.kind == ContactKind::kTool && moved_tools_[c.b]);
    if (!involved) kept_.push_back(c);
  }
  memory_.candidates.swap(kept_);
  detector_.DetectAround(spheres, obstacles, tools, moved_spheres_, moved_tools_,
                         &memory_.candidates, memory_.searched_margin);
  for (size_t i = 0; i < n; ++i) {
    if (moved_spheres_[i]) memory_.centres_at_search[i] = spheres[i].centre;
  }
  for (size_t t = 0; t < tools.size(); ++t) {
    if (moved_tools_[t]) memory_.tools_at_search[t] = tools[t];
  }
  memory_.drift = std::max(memory_.drift, left);
  memory_.stamp = NextStamp();
  ++partial_searches_;
  return true;
}

}  // namespace viscera::collision
