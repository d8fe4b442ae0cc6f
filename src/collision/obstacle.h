#pragma once
/// Rigid obstacles of the environment (other organs, the abdominal cavity, a table) as signed
/// distance functions. The distance is positive in free space and the normal points into it, so
/// `inside = true` (the abdominal cavity, holding the intestine inside) just flips the sign.
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "collision/mesh_sdf.h"
#include "common/types.h"

namespace viscera::collision {

enum class ObstacleKind { kPlane, kSphere, kCapsule, kBox, kEllipsoid, kMesh };

struct Obstacle {
  ObstacleKind kind = ObstacleKind::kPlane;
  std::string name;
  bool inside = false;                      ///< the free space is inside the shape (a cavity)
  Vec3 point = Vec3::Zero();                ///< plane: a point on it
  Vec3 normal = Vec3::UnitZ();              ///< plane: unit normal toward free space
  Vec3 centre = Vec3::Zero();               ///< sphere, box, ellipsoid
  double radius = 0.0;                      ///< sphere, capsule
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();  ///< capsule axis ends
  Vec3 half_extents = Vec3::Zero();         ///< box
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< box, ellipsoid
  Vec3 radii = Vec3::Zero();                                        ///< ellipsoid semi-axes
  std::shared_ptr<const MeshSdf> sdf;                               ///< mesh
};

/// Signed distance (m) from p to the obstacle's surface, positive in free space; `normal` (unit)
/// points toward free space. For the ellipsoid the distance is a first-order estimate, exact on
/// the surface and at the centre.
double SignedDistance(const Obstacle& o, const Vec3& p, Vec3* normal);
/// The same distance without the normal, cheaper for a mesh (the broad phase's query).
double SignedDistance(const Obstacle& o, const Vec3& p);

/// An obstacle with what every query of its frame needs (a box's or an ellipsoid's rotation
/// matrix, an ellipsoid's inverse radii) computed once: the narrow phase queries the cavity for
/// every sphere at every sub-step. Holds its own copy of the obstacle, which it never changes,
/// so the prepared values cannot go stale. Its distances are SignedDistance's, bit for bit (the
/// same expressions on the same values).
class PreparedObstacle {
 public:
  explicit PreparedObstacle(Obstacle obstacle);

  const Obstacle& obstacle() const { return obstacle_; }
  /// SignedDistance(obstacle(), p, normal).
  double SignedDistance(const Vec3& p, Vec3* normal) const;

  /// The per-query constants of an obstacle's frame (identity and zero where its kind has none).
  struct Frame {
    Mat3 rotation = Mat3::Identity();  ///< box, ellipsoid: orientation as a matrix
    Vec3 inv_radii = Vec3::Zero();     ///< ellipsoid: 1 / radii
  };
  static Frame FrameOf(const Obstacle& o);

 private:
  Obstacle obstacle_;
  Frame frame_;
};

}  // namespace viscera::collision
