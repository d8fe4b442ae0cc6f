#pragma once
/// The laparoscope of a scene's [camera]: a scope through its port, forward or oblique optics,
/// its light a spot at the tip. And the default view of a scene: that scope, else the framing.
#include "mechanics/model_params.h"
#include "render/laparoscope.h"

namespace viscera::render {

/// Fraction of the spot's outer half angle within which its light is at full strength.
inline constexpr float kSpotInnerFraction = 0.6f;

/// The tip sits `insertion` past the port along the shaft (port toward look_at); the line of
/// sight leaves it `optics` degrees off the shaft, toward the bottom of the image turned by
/// `roll` about the shaft (0 bottom, 90 right); `up` stays up in the image (the camera head is
/// held level while the optics turn). The look-at is on the line of sight, as far from the tip
/// as the scene's look_at (at least 2 cm): the hybrid skin's focus.
/// @pre `scope` as ReadCamera validates it.
Laparoscope PortLaparoscope(const mechanics::ScopeParams& scope);

/// A scene's default view: its [camera] scope, else FramingLaparoscope of the control points
/// `q` (#N by 3) for a width x height frame.
Laparoscope SceneLaparoscope(const mechanics::ModelParams& params, const Points& q, int width,
                             int height);

}  // namespace viscera::render
