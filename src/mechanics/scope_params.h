#pragma once
/// The scene's laparoscope ([camera]; docs/scenes.md): a scope through a port, its optics and its
/// light. Plain data that rides with the model so the frame streams, the exposure and viscera-sim
/// all look through the same scope; the mechanics never read it.
#include "common/types.h"

namespace viscera::mechanics {

struct ScopeParams {
  Vec3 port = Vec3::Zero();     ///< trocar point in the abdominal wall (m)
  Vec3 look_at = Vec3::Zero();  ///< a point the shaft aims at (m), not the port
  double insertion = 0.05;      ///< m of scope past the port: the tip, with the lens and the light
  /// Angle between the shaft and the line of sight (degrees): 0 forward-viewing, 30 the usual
  /// oblique scope.
  double optics_deg = 0.0;
  /// Which way oblique optics look, turning the scope about its shaft (degrees): 0 toward the
  /// bottom of the image (light post up, the usual hold), 90 right, 180 top, 270 left.
  double roll_deg = 0.0;
  double fov_deg = 70.0;      ///< vertical field of view
  double light_range = 0.22;  ///< m from the tip where the light has fallen to half
  double light_cone_deg =
      60.0;  ///< half angle of the spot where its light has faded out (full within 0.6 of it)
  Vec3 up = Vec3::UnitZ();  ///< the world direction shown up in the image
};

}  // namespace viscera::mechanics
