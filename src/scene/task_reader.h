#pragma once
/// Reads the training task of a scene: [[target]] patches to expose and the [assessment]
/// thresholds (docs/scenes.md, docs/assessment.md).
#include <vector>

#include "mechanics/model_params.h"
#include "scene/toml_fwd.h"

namespace viscera::scene {

/// Fills p->task from the [[target]] tables and the [assessment] table (nullptr: defaults).
/// Reads after the intestine (a target's samples are bounded) and the obstacles.
/// @throws InputError naming the key, the value and the reason.
void ReadTask(const std::vector<const toml::table*>& targets, const toml::table* assessment,
              mechanics::ModelParams* p);

/// Fills p->task.running from the [running] table (docs/training.md).
/// @throws InputError naming the key, the value and the reason.
void ReadRunning(const toml::table& running, mechanics::ModelParams* p);

/// Most sample points a target may ask for (each costs one ray per exposure evaluation).
inline constexpr int kMaxTargetSamples = 1024;
/// Most targets a scene may declare.
inline constexpr int kMaxTargets = 16;

}  // namespace viscera::scene
