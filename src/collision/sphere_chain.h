#pragma once
/// The chain of equal spheres that stands for the tube in collisions (France et al. 2005,
/// section 3.5, Figure 2): radius = tube radius, spread uniformly by arc length along the
/// current curve and re-placed every step. Their number depends on the tube's rest length and
/// radius only (spacing = radius), never on the number of control points.
#include <array>
#include <vector>

#include "common/types.h"
#include "spline/arc_length.h"
#include "spline/catmull_rom.h"

namespace viscera::collision {

struct Sphere {
  double s = 0.0;             ///< curve parameter of the centre
  int first = 0;              ///< first control point of its window
  std::array<double, 4> w{};  ///< b_{first+a}(s): maps forces to generalized forces
  Vec3 centre = Vec3::Zero();
};

class SphereChain {
 public:
  /// @pre radius > 0, rest_length > 0.
  SphereChain(const spline::CatmullRom& curve, double rest_length, double radius);

  /// Re-places the spheres uniformly by arc length on pose q (#N by 3). Allocates nothing.
  void Place(const Points& q);
  /// Moves the centres with q, keeping each sphere's curve parameter (within a step).
  void UpdateCentres(const Points& q);

  const std::vector<Sphere>& spheres() const { return spheres_; }
  double radius() const { return radius_; }
  /// Chain distance between neighbours at rest (m).
  double spacing() const { return spacing_; }
  int size() const { return static_cast<int>(spheres_.size()); }

 private:
  const spline::CatmullRom& curve_;
  double radius_, spacing_;
  spline::ArcLengthTable table_;
  std::vector<Sphere> spheres_;
};

}  // namespace viscera::collision
