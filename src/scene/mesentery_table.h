#pragma once
/// The [mesentery] table of a scene (docs/scenes.md): the root line, the tethers' slack length
/// profile and their stiffness.
#include <optional>

#include "mechanics/model_params.h"
#include "scene/toml_fwd.h"

namespace viscera::scene {

/// The anatomical default profile (docs/scenes.md): short at the duodenojejunal flexure and the
/// ileocecal junction, about 20 cm in the middle of the small intestine.
std::vector<std::pair<double, double>> DefaultMesenteryLengths();

/// Reads [mesentery] when the scene has one.
/// @throws InputError naming the key, the value and the reason.
std::optional<mechanics::MesenteryParams> ReadMesentery(const toml::table& root);

}  // namespace viscera::scene
