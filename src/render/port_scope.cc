#include "render/port_scope.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace viscera::render {

Laparoscope PortLaparoscope(const mechanics::ScopeParams& scope) {
  const Vec3 shaft = (scope.look_at - scope.port).normalized();
  const Vec3 tip = scope.port + scope.insertion * shaft;
  // the image frame of forward optics: right and up across the shaft
  const Vec3 right = shaft.cross(scope.up).normalized();
  const Vec3 image_up = right.cross(shaft);
  const double roll = scope.roll_deg * std::numbers::pi / 180.0;
  const double tilt = scope.optics_deg * std::numbers::pi / 180.0;
  const Vec3 side =
      -std::cos(roll) * image_up + std::sin(roll) * right;  // where oblique optics look
  const Vec3 sight = std::cos(tilt) * shaft + std::sin(tilt) * side;
  const double reach = std::max((scope.look_at - tip).norm(), 0.02);

  Laparoscope l;
  l.eye = tip.cast<float>();
  l.target = (tip + reach * sight).cast<float>();
  l.up = scope.up.cast<float>();
  l.fov_y_degrees = static_cast<float>(scope.fov_deg);
  l.light_range = static_cast<float>(scope.light_range);
  l.spot_outer_deg = static_cast<float>(scope.light_cone_deg);
  l.spot_inner_deg = kSpotInnerFraction * l.spot_outer_deg;
  return l;
}

Laparoscope SceneLaparoscope(const mechanics::ModelParams& params, const Points& q, int width,
                             int height) {
  if (params.scope) return PortLaparoscope(*params.scope);
  return FramingLaparoscope(q.colwise().minCoeff().transpose(), q.colwise().maxCoeff().transpose(),
                            width, height);
}

}  // namespace viscera::render
