#pragma once
/// What the viewer page needs to draw a session itself (client/web/viewer.js): the scene's
/// static geometry tessellated as the server's renderer does (cavity wall, organs, targets), its
/// materials, the tube's dimensions, the tools' ports and the laparoscope's matrices; and each
/// skeleton state as a small JSON message. The page builds the intestine from the skeleton.
#include <string>
#include <vector>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/session_request_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "mechanics/model_params.h"

namespace viscera::client {

/// Reads a scene file for its geometry only (no settling: the page needs shapes, not a state).
/// @throws InputError as scene::LoadSceneFile.
mechanics::ModelParams LoadSceneGeometry(const std::string& path);

/// The page's scene as JSON: frame size, camera (view and projection, column-major, and the
/// light), background, tube (length, radius, parametric skin's ring radii and tessellation),
/// materials, static meshes, tools and mesentery. The camera is the server's default view
/// (render::SceneLaparoscope) of `first` (the session's skeleton when the viewer started).
/// @throws InputError when `first` does not match the scene's control points.
std::string SceneJson(const mechanics::ModelParams& params,
                      const viscera_proto::skeleton_state_t& first, int width, int height);

/// Latest state of one tool as the viewer sees it on the bus: the simulated tip (force
/// feedback) and the jaws' orientation and opening (the latest pose).
struct ViewedTool {
  bool seen = false;  ///< a force message said the tool was driven
  double tip[3] = {0, 0, 0};
  double orientation[4] = {1, 0, 0, 0};
  double jaw = 1.0;
};

/// The camera a client set (a kCamera request the server accepted), as the page takes it: the
/// server draws it as render::LookAtLaparoscope (a plain camera: no spot cone).
/// @throws InputError for a camera the renderer could not use.
std::string LookAtCameraJson(const viscera_proto::session_request_t& request, int width,
                             int height);

/// One skeleton message for the page: step, sim time, send time (us), control points
/// (flattened, 6 significant digits), the tools' triangles (tessellated as the server draws
/// them) and, when not empty, the camera a client set (LookAtCameraJson).
std::string SkeletonJson(const viscera_proto::skeleton_state_t& state,
                         const mechanics::ModelParams& params, const std::vector<ViewedTool>& tools,
                         const std::string& camera);

}  // namespace viscera::client
