#pragma once
/// Contact candidates kept across sub-steps and steps while nothing moved far (Verlet lists,
/// Verlet 1967): the search runs with `skin` more margin than asked, and the list stays valid
/// until some sphere or tool tip has moved by half the spare margin since that search. A pile
/// that barely moves between 1 kHz steps is searched once every few tens of steps instead of
/// twice per sub-step; the obstacles' distance fields are queried only then.
#include <cstdint>
#include <vector>

#include "collision/contact_detector.h"

namespace viscera::collision {

class VerletList {
 public:
  /// @param skin extra margin (m) searched beyond what is asked; the larger, the longer a list
  ///   lives and the more far pairs the narrow phase looks at.
  /// @pre skin > 0.
  VerletList(ContactDetector detector, double skin);

  /// Makes candidates() hold every pair whose gap is below `margin` now (and some farther: the
  /// caller checks distances). Searches again only when the kept list may miss one. Returns
  /// whether it searched. Allocates nothing once its buffers have grown.
  bool Update(const std::vector<Sphere>& spheres, const std::vector<Obstacle>& obstacles,
              const std::vector<ToolCapsule>& tools, double margin);
  /// The next Update searches again (state restored, model changed).
  void Invalidate() { valid_ = false; }

  const std::vector<ContactCandidate>& candidates() const { return candidates_; }
  int64_t searches() const { return searches_; }

 private:
  // Largest displacement of a sphere centre or a tool tip since the last search (m).
  double Travel(const std::vector<Sphere>& spheres, const std::vector<ToolCapsule>& tools) const;

  ContactDetector detector_;
  double skin_;
  bool valid_ = false;
  double searched_margin_ = 0.0;  // the margin of the last search (asked + skin)
  std::vector<Vec3> centres_at_search_;
  std::vector<ToolCapsule> tools_at_search_;
  std::vector<ContactCandidate> candidates_;
  int64_t searches_ = 0;
};

}  // namespace viscera::collision
