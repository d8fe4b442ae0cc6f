#pragma once
/// Tool paths for `viscera drive`: the project's tool-script format (src/script, a CSV
/// `t,tool,x,y,z,qw,qx,qy,qz,jaw`, the same files viscera-sim plays), and the built-in
/// clearing gesture.
#include <string>

#include "script/tool_script.h"

namespace viscera::client {

/// The clearing gesture of scenes/clearing.csv (embedded at build time), so that a client
/// needs no file:
/// on scenes/cavity.toml the "right" grasper comes down on the loop lying over the lesion,
/// grasps it, lifts it, moves it aside, lays it down, releases it and withdraws (5.5 s).
script::ToolScript ClearingGesture();

/// A tool script from a file. @throws InputError naming the file, line and column.
script::ToolScript LoadScript(const std::string& path);

}  // namespace viscera::client
