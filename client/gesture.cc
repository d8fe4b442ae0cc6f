#include "client/gesture.h"

namespace viscera::client {
namespace {

// scenes/clearing.csv, keyframes only (a test checks that the two agree).
constexpr char kClearing[] = R"(t,tool,x,y,z,qw,qx,qy,qz,jaw
0.0,left,-0.012,-0.010,0.160,1,0,0,0,1
1.0,left,-0.012,-0.010,0.097,1,0,0,0,1
1.5,left,-0.012,-0.010,0.097,1,0,0,0,0
2.5,left,-0.012,-0.010,0.150,1,0,0,0,0
3.5,left,-0.080,0.040,0.150,1,0,0,0,0
4.0,left,-0.080,0.040,0.120,1,0,0,0,0
4.5,left,-0.080,0.040,0.120,1,0,0,0,1
5.5,left,-0.080,0.040,0.200,1,0,0,0,1
)";

}  // namespace

script::ToolScript ClearingGesture() { return script::ToolScript::Parse(kClearing, "clearing"); }

script::ToolScript LoadScript(const std::string& path) { return script::ToolScript::Load(path); }

}  // namespace viscera::client
