// End to end, in a loopback-only namespace: hostile inputs against a real viscerad with a
// witness session beside them (docs/security.md, "Limits"). Each test asserts the refusal's
// reason, the server alive afterwards and the witness still stepping.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "tests/e2e/e2e_harness.h"

namespace viscera::e2e {
namespace {

using nlohmann::json;

std::string Repeat(const std::string& part, int n) {
  std::string out;
  for (int i = 0; i < n; ++i) out += part;
  return out;
}

const std::string kBase = "[intestine]\nlength = 0.4\nradius = 0.0125\nmass = 0.1\ncontrol_points = 21\n"
                          "[intestine.shape]\nkind = \"straight\"\n";

// The witness runs on: its step count grows by more than `steps` within 30 s.
void ExpectWitnessSteps(const std::string& dir, int64_t id, int64_t steps = 20, const std::string& extra = "") {
  const json first = Status(dir, id, extra);
  ASSERT_EQ(first["state"], "running") << first.dump();
  const int64_t from = first["steps"].get<int64_t>();
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  json s;
  while (std::chrono::steady_clock::now() < give_up) {
    s = TryStatus(dir, id, extra);
    if (!s.is_null() && s["steps"].get<int64_t>() > from + steps) break;
    Sleep(0.1);
  }
  ASSERT_FALSE(s.is_null());
  EXPECT_EQ(s["state"], "running");
  EXPECT_GT(s["steps"].get<int64_t>(), from + steps) << "the witness stopped stepping";
}

// Sends `scene` inline (create --scene-file) and expects a refusal whose text holds `reason`.
void ExpectRefused(const std::string& dir, const std::string& scene, const std::string& reason) {
  const std::string file = dir + "/hostile.toml";
  std::ofstream(file) << scene;
  const CliResult r = Viscera(dir, "create --scene-file " + file + " --frame-rate -1 --timeout 30 2>&1");
  EXPECT_EQ(r.rc, 4) << r.out;
  EXPECT_NE(r.out.find(reason), std::string::npos) << r.out.substr(0, 2000);
}

// The one-packet crash: an ~80 KB inline scene whose dotted key or [x.x.x...] header nests
// 40,000 deep made the TOML parser overflow the build thread's stack.
TEST(HostileE2E, ADeepDottedKeyOrHeaderIsRefusedAndTheServerLivesOn) {
  const std::string dir = ScratchDir();
  Daemon daemon("hostile-a", {}, dir);
  const int64_t witness = Create(dir, "hanging --frame-rate -1")["session"].get<int64_t>();
  const std::string deep = Repeat("x.", 40000) + "x";
  ExpectRefused(dir, kBase + deep + " = 1\n", "a dotted key or [table] header nests deeper than the limit of 16");
  ExpectRefused(dir, kBase + "[" + deep + "]\n", "a dotted key or [table] header nests deeper than the limit of 16");
  EXPECT_TRUE(daemon.Alive()) << daemon.Stderr();
  ExpectWitnessSteps(dir, witness);
  EXPECT_EQ(daemon.Stop(), 0);
}

std::string Tools(int n, const std::string& extra = "") {
  std::string out;
  for (int i = 0; i < n; ++i) out += "[[tool]]\nname = \"t" + std::to_string(i) + "\"\nport = [0, 0, 0.3]\n" + extra;
  return out;
}

// What a scene would cost, bounded from its keys before anything is allocated: a tiny radius
// (6.2 GB in 23 s), a huge contact margin (no reply for 120 s), 300 tools (2.9 GB of queued
// forces), and tool parameters that put NaN on the wire.
TEST(HostileE2E, CostlyScenesAreRefusedWithTheKeyAndTheLimit) {
  const std::string dir = ScratchDir();
  Daemon daemon("hostile-b", {}, dir);
  const int64_t witness = Create(dir, "hanging --frame-rate -1")["session"].get<int64_t>();
  const std::string tiny = "[intestine]\nlength = 0.4\nradius = 1e-7\nmass = 0.1\ncontrol_points = 21\n"
                           "[intestine.shape]\nkind = \"straight\"\n";
  ExpectRefused(dir, tiny, "intestine.length / intestine.radius = 4e+06 collision spheres: above this server's limit of 2000");
  ExpectRefused(dir, kBase + "[contacts]\nmargin = 10.0\n",
                "contacts.margin = 10 m: above this server's limit of 4 tube radii");
  ExpectRefused(dir, kBase + Tools(300), "[[tool]] count = 300: above this server's limit of 8");
  ExpectRefused(dir, kBase + Tools(1, "coupling_stiffness = 1e308\n"), "tool[0].coupling_stiffness = 1e+308: outside");
  ExpectRefused(dir, kBase + Tools(1, "max_force = 1e308\n"), "tool[0].max_force = 1e+308: outside");
  ExpectRefused(dir, kBase + Tools(1, "mass = 1e-300\n"), "tool[0].mass = 1e-300: expected 0.001..10 kg");
  EXPECT_TRUE(daemon.Alive()) << daemon.Stderr();
  ExpectWitnessSteps(dir, witness);
  EXPECT_EQ(daemon.Stop(), 0);
}

}  // namespace
}  // namespace viscera::e2e
