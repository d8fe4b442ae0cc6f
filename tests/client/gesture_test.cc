#include "client/gesture.h"

#include <gtest/gtest.h>

namespace viscera::client {
namespace {

TEST(Gesture, TheBuiltInClearingGestureIsScenesClearingCsv) {
  const script::ToolScript built_in = ClearingGesture();
  const script::ToolScript file =
      LoadScript(std::string(VISCERA_SOURCE_DIR) + "/scenes/clearing.csv");
  ASSERT_EQ(built_in.tools(), file.tools());
  EXPECT_EQ(built_in.duration(), file.duration());
  EXPECT_GT(built_in.duration(), 1.0);
  for (const std::string& tool : file.tools()) {
    for (double t = 0.0; t <= file.duration(); t += 0.05) {
      const auto a = built_in.At(tool, t);
      const auto b = file.At(tool, t);
      EXPECT_EQ(a.tip, b.tip) << tool << " at " << t;
      EXPECT_EQ(a.jaw, b.jaw) << tool << " at " << t;
    }
  }
}

}  // namespace
}  // namespace viscera::client
