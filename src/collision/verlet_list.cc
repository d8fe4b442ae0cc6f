#include "collision/verlet_list.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace viscera::collision {

VerletList::VerletList(ContactDetector detector, double skin) : detector_(detector), skin_(skin) {
  ThrowUnless(skin > 0.0, "Verlet list skin ", skin, " m: must be > 0");
}

double VerletList::Travel(const std::vector<Sphere>& spheres, const std::vector<ToolCapsule>& tools) const {
  double worst = 0.0;
  for (size_t i = 0; i < spheres.size(); ++i) {
    worst = std::max(worst, (spheres[i].centre - centres_at_search_[i]).squaredNorm());
  }
  for (size_t t = 0; t < tools.size(); ++t) {
    // A capsule pivoting at a fixed port: no point of the shaft moves farther than its tip.
    worst = std::max(worst, (tools[t].tip - tools_at_search_[t].tip).squaredNorm());
    worst = std::max(worst, (tools[t].port - tools_at_search_[t].port).squaredNorm());
  }
  return std::sqrt(worst);
}

bool VerletList::Update(const std::vector<Sphere>& spheres, const std::vector<Obstacle>& obstacles,
                        const std::vector<ToolCapsule>& tools, double margin) {
  bool same_bodies = valid_ && spheres.size() == centres_at_search_.size() && tools.size() == tools_at_search_.size();
  for (size_t t = 0; same_bodies && t < tools.size(); ++t) {
    same_bodies = tools[t].present == tools_at_search_[t].present && tools[t].radius == tools_at_search_[t].radius;
  }
  // A pair left out had a gap of at least searched_margin_ at the search. Distances between
  // bodies are 1-Lipschitz in each body's displacement, so its gap now is at least
  // searched_margin_ - 2 * travel (two spheres closing in on each other).
  if (same_bodies && searched_margin_ - 2.0 * Travel(spheres, tools) >= margin) return false;

  searched_margin_ = margin + skin_;
  detector_.Detect(spheres, obstacles, tools, &candidates_, searched_margin_);
  centres_at_search_.resize(spheres.size());
  for (size_t i = 0; i < spheres.size(); ++i) centres_at_search_[i] = spheres[i].centre;
  tools_at_search_ = tools;  // same size after the first search: no allocation
  valid_ = true;
  ++searches_;
  return true;
}

}  // namespace viscera::collision
