#pragma once
/// The [camera] table of a scene (docs/scenes.md): the laparoscope's port, aim, optics and light.
#include <optional>

#include "mechanics/scope_params.h"
#include "scene/toml_fwd.h"

namespace viscera::scene {

/// Reads [camera] when the scene has one (else the plain framing camera is used).
/// @throws InputError naming the key, the value and the reason.
std::optional<mechanics::ScopeParams> ReadCamera(const toml::table& root);

}  // namespace viscera::scene
