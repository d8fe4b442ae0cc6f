#pragma once
/// The laparoscope a session is seen through, one definition for the frame stream and the
/// exposure watcher (so the exposure counts what the frames show): the client's camera once it
/// set one, else the scene's laparoscope ([camera]) or the framing of the scene as first seen.
#include "render/laparoscope.h"
#include "render/port_scope.h"
#include "session/session.h"

namespace viscera::server {

/// The scene's own view: its [camera] scope, else the framing of the control points `q` (#N by 3)
/// for a width x height frame.
inline render::Laparoscope FirstFraming(const mechanics::ModelParams& params, const Points& q,
                                        int width, int height) {
  return render::SceneLaparoscope(params, q, width, height);
}

/// The client's camera if it set one, else `framing`.
inline render::Laparoscope SessionScope(const session::CameraPose& pose,
                                        const render::Laparoscope& framing) {
  return pose.set_by_client
             ? render::LookAtLaparoscope(pose.eye, pose.target, pose.up, pose.fov_deg)
             : framing;
}

}  // namespace viscera::server
