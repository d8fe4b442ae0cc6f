#pragma once
/// A tool script driving a simulation's tools directly, in-process (viscera-sim, benchmarks,
/// tests): what `viscera drive` does over the bus, without the bus. Its own library, so that the
/// script parser stays free of the mechanics.
#include <span>
#include <string>
#include <vector>

#include "mechanics/interactions.h"
#include "mechanics/model.h"
#include "mechanics/state.h"
#include "script/script_player.h"

namespace viscera::script {

class ScriptedTools {
 public:
  /// @throws InputError if the script names a tool the model does not have.
  ScriptedTools(const mechanics::Model& model, ToolScript script,
                const std::string& source = "<script>");

  /// Targets of the model's tools at time t, in scene order (tools the script does not name are
  /// idle). Rows aimed at the tube aim at the sphere chain's centres as `interactions` holds
  /// them (null: their written positions); grasp rows are checked against the tools' tips in
  /// `state` (null: unchecked).
  std::span<const mechanics::ToolTarget> At(double t, const mechanics::Interactions* interactions,
                                            const mechanics::State* state = nullptr);
  double duration() const { return player_.script().duration(); }
  /// How far the script runs behind the clock after reaches played again (ScriptPlayer).
  double delay() const { return player_.delay(); }
  const ScriptPlayer& player() const { return player_; }

 private:
  const mechanics::Model& model_;
  ScriptPlayer player_;
  std::vector<mechanics::ToolTarget> targets_;
  Tube tube_;
};

}  // namespace viscera::script
