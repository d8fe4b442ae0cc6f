#pragma once
/// Contact candidates kept across sub-steps and steps while nothing moved far (Verlet lists,
/// Verlet 1967): the search runs with `skin` more margin than asked, and the list stays valid
/// while no body (sphere or tool) can have closed the spare margin. A pile that barely moves
/// between 1 kHz steps is searched once every few tens of steps instead of twice per sub-step;
/// the obstacles' distance fields are queried only then. When only a few bodies moved far (a
/// grasped loop, a tool), only they are searched again (a partial search): the whole pile's
/// search made the 1 kHz steps' p99 (docs/contacts.md, "Broad phase").
#include <cstdint>
#include <vector>

#include "collision/contact_detector.h"

namespace viscera::collision {

/// What a Verlet list carries from one update to the next: the candidates and where each body was
/// when last searched. Plain data, so that a simulation's state can hold it (mechanics::State):
/// the candidates' order is the order in which contacts are summed, so a run continued from a
/// copied state must start from the same list to round the same.
struct VerletMemory {
  bool valid = false;
  /// Which search left this list: a copy keeps it, every search gives a new one (unique within
  /// the process; 0: never searched). Equal stamps mean equal contents.
  uint64_t stamp = 0;
  double searched_margin = 0.0;         ///< the margin of the last whole search (asked + skin)
  double drift = 0.0;                   ///< largest travel of a body a partial search left alone
  std::vector<Vec3> centres_at_search;  ///< each sphere where it was last searched
  std::vector<ToolCapsule> tools_at_search;  ///< each tool where it was last searched
  std::vector<ContactCandidate> candidates;
};

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
  void Invalidate() {
    memory_.valid = false;
    memory_.stamp = NextStamp();
  }

  const std::vector<ContactCandidate>& candidates() const { return memory_.candidates; }
  /// What the next Update starts from.
  const VerletMemory& memory() const { return memory_; }
  /// Continues from `memory` (a copy of what memory() was, in this list or another with the same
  /// detector and skin). Returns whether that changed anything (its stamp differs); allocates
  /// nothing once the buffers hold the largest list seen.
  bool Restore(const VerletMemory& memory);
  /// Whole searches and partial ones (the bodies that moved far) so far.
  int64_t searches() const { return searches_; }
  int64_t partial_searches() const { return partial_searches_; }

 private:
  // Each body's displacement since it was last searched (m): spheres, then tools (a capsule
  // pivoting at its port: no point of the shaft moves farther than its tip or port).
  void MeasureTravel(const std::vector<Sphere>& spheres, const std::vector<ToolCapsule>& tools);
  // Searches again the bodies that moved farther than `threshold`; false if too many did.
  bool SearchMoved(const std::vector<Sphere>& spheres, const std::vector<Obstacle>& obstacles,
                   const std::vector<ToolCapsule>& tools, double threshold);

  // A partial search needs some spare margin left (else the whole search, which restores the
  // skin) and few bodies to search (else the whole search is cheaper): 1/kPartialShare of them.
  static constexpr double kLeastPartialSpare = 0.125;
  static constexpr size_t kPartialShare = 4;

  // A new stamp for a search's result.
  static uint64_t NextStamp();

  ContactDetector detector_;
  double skin_;
  VerletMemory memory_;
  std::vector<double> travel_;  // per body, MeasureTravel's
  std::vector<char> moved_spheres_, moved_tools_;
  std::vector<ContactCandidate> kept_;
  int64_t searches_ = 0, partial_searches_ = 0;
};

}  // namespace viscera::collision
