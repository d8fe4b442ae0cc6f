#pragma once
/// Laparoscope: the camera a trainee looks through. A pose (eye, look-at, up), a wide
/// field of view, and a light carried at the eye. Its matrices drive MeshRenderer.
#include <Eigen/Core>

#include "common/types.h"
#include "render/mesh_renderer.h"

namespace viscera::render {

struct Laparoscope {
  Eigen::Vector3f eye{0.0f, -0.1f, 0.3f};    ///< lens position (m, world)
  Eigen::Vector3f target{0.0f, 0.0f, 0.0f};  ///< look-at point (m, world)
  Eigen::Vector3f up{0.0f, 0.0f, 1.0f};      ///< roughly up in the image (world)
  float fov_y_degrees = 70.0f;  ///< vertical field of view (laparoscopes see wide: 70-90 degrees)
  float near = 0.002f;          ///< clip planes (m): the lens may come within mm of tissue
  float far = 3.0f;
  /// Distance (m) at which the scope's light falls to half (CameraMatrices::light_range).
  float light_range = 0.25f;
  /// The light's spot cone about the line of sight (CameraMatrices): half angles (degrees) of
  /// full strength and of none. 0: no cone (a plain camera).
  float spot_inner_deg = 0.0f;
  float spot_outer_deg = 0.0f;

  /// View and projection for a frame of width x height pixels.
  /// @throws InputError for a degenerate pose (eye == target, up along the view) or
  ///         values out of range (see LookAt, Perspective).
  CameraMatrices Matrices(int width, int height) const;
};

/// Pixel (column, row from the top, continuous: pixel centres at +0.5) where a world point
/// projects in a width x height frame, and its depth in front of the eye (m; <= 0 behind).
struct Projection {
  Eigen::Vector2f pixel;
  float depth = 0.0f;
};
Projection Project(const CameraMatrices& camera, int width, int height,
                   const Eigen::Vector3f& point);

/// A scope at `eye` looking at `target`, its light reaching half strength at 1.5 times
/// that distance (as FramingLaparoscope), other values the defaults.
Laparoscope LookAtLaparoscope(const Vec3& eye, const Vec3& target, const Vec3& up = Vec3::UnitZ(),
                              double fov_y_degrees = 70.0);

/// The default view of a scene: looking at the centre of the box [lo, hi] from above and
/// in front (from -y and +z, 50 degrees above the horizontal: the surgeon's side of the
/// abdomen in the shipped scenes), far enough that the box's bounding sphere fits in the
/// narrower field of view of a width x height frame; the light reaches half strength at
/// 1.5 times that distance.
/// @pre lo <= hi componentwise.
Laparoscope FramingLaparoscope(const Vec3& lo, const Vec3& hi, int width, int height);

}  // namespace viscera::render
