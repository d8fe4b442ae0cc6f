#pragma once
/// Finds the contact candidates of a sphere chain: self pairs through the spatial grid, spheres
/// near obstacles, spheres near tool capsules. "Near" is within the contact distance plus a
/// margin, so that pairs closing in during a step are already known. Deterministic order.
#include <vector>

#include "collision/obstacle.h"
#include "collision/spatial_grid.h"
#include "collision/sphere_chain.h"

namespace viscera::collision {

enum class ContactKind : int { kSelf = 0, kEnvironment = 1, kTool = 2 };

struct ContactCandidate {
  ContactKind kind = ContactKind::kSelf;
  int a = 0;  ///< sphere
  int b = 0;  ///< other sphere (self), obstacle index (environment), tool index (tool)
};

/// A tool's shaft: the capsule from the trocar port to the tip.
struct ToolCapsule {
  bool present = false;  ///< false until the tool has been placed
  Vec3 port = Vec3::Zero();
  Vec3 tip = Vec3::Zero();
  double radius = 0.0;
};

/// Closest point of segment [port, tip] to p, and its fraction along it (0 = port, 1 = tip).
Vec3 ClosestOnSegment(const Vec3& port, const Vec3& tip, const Vec3& p, double* fraction);

class ContactDetector {
 public:
  /// @param self_skip self pairs closer than this many spheres along the chain are ignored.
  ContactDetector(double radius, double margin, bool self_contacts, int self_skip);

  /// Fills `out` (cleared first) with everything within the contact distance plus `margin`
  /// (the constructor's margin when negative). Allocates nothing once its capacity has grown.
  void Detect(const std::vector<Sphere>& spheres, const std::vector<Obstacle>& obstacles,
              const std::vector<ToolCapsule>& tools, std::vector<ContactCandidate>* out,
              double margin = -1.0);

  /// Appends to `out` every candidate Detect would find that involves a sphere marked in
  /// `moved_spheres` or a tool marked in `moved_tools`, each once (the Verlet list's partial
  /// search). Allocates nothing once its capacity has grown.
  void DetectAround(const std::vector<Sphere>& spheres, const std::vector<Obstacle>& obstacles,
                    const std::vector<ToolCapsule>& tools, const std::vector<char>& moved_spheres,
                    const std::vector<char>& moved_tools, std::vector<ContactCandidate>* out,
                    double margin);

  int self_skip() const { return self_skip_; }

 private:
  double Extra(double margin) const { return margin >= 0.0 ? margin : margin_; }
  bool NearObstacle(const Sphere& s, const Obstacle& o, double extra) const;
  bool NearTool(const Sphere& s, const ToolCapsule& t, double extra) const;

  double radius_, margin_;
  bool self_;
  int self_skip_;
  SpatialGrid grid_;
  std::vector<Vec3> centres_;
};

}  // namespace viscera::collision
