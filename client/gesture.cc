#include "client/gesture.h"

#include "client/clearing_gesture.h"  // generated from scenes/clearing.csv

namespace viscera::client {

script::ToolScript ClearingGesture() {
  return script::ToolScript::Parse(generated::kClearingCsv, "clearing");
}

script::ToolScript LoadScript(const std::string& path) { return script::ToolScript::Load(path); }

}  // namespace viscera::client
