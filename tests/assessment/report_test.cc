// The assessment report: its JSON and its status fields carry every figure exactly.
#include <gtest/gtest.h>

#include "assessment/report.h"
#include "assessment/status_report.h"

namespace viscera::assessment {
namespace {

Report Sample() {
  Report r;
  r.session = 42;
  r.scene = "cavity";
  r.sim_time = 12.345678901234;
  r.finished = true;
  r.thresholds = {3.0, 0.5, 1.0, 0.9};
  r.tools.push_back(
      {"left", 0.30123456789, 4.5, 0.58, 0.99, 1.0912345, 3.4, 2, 1.25, 3, 1, 4, 0.07});
  r.tools.push_back({"right", 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0, 0.0, 0, 0, 0, 0.0});
  r.targets.push_back({"lesion", 1.0, 1.0, 2.0});
  r.targets.push_back({"hidden", 0.125, 0.25, -1.0});  // not exposed: null in JSON
  return r;
}

TEST(Report, JsonRoundTripsExactly) {
  const Report r = Sample();
  const nlohmann::json j = ToJson(r);
  EXPECT_TRUE(j["targets"][1]["time_to_expose_s"].is_null());
  EXPECT_EQ(ReportFromJson(nlohmann::json::parse(j.dump())), r);
  // and a changed figure is seen (the comparison is not vacuous)
  Report other = r;
  other.tools[0].regrasps = 2;
  EXPECT_FALSE(ReportFromJson(j) == other);
}

TEST(Report, JsonMissingAKeyIsAnError) {
  nlohmann::json j = ToJson(Sample());
  j["tools"][0].erase("grasps");
  EXPECT_THROW(ReportFromJson(j), nlohmann::json::exception);
}

// `r` in a stopped session's status, through LCM's encoding as a status travels, read back.
Report ThroughTheWire(const Report& r) {
  viscera_proto::session_status_t s{};
  s.header.session_id = r.session;
  s.scene = r.scene;
  s.sim_time = r.sim_time;
  s.state = viscera_proto::session_status_t::kStopped;
  s.num_tools = 2;
  s.tool_names = {"left", "right"};
  FillStatus(r, &s);
  std::vector<uint8_t> bytes(static_cast<size_t>(s.getEncodedSize()));
  EXPECT_EQ(s.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  viscera_proto::session_status_t decoded;
  EXPECT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  return ReportFromStatus(decoded);
}

TEST(Report, StatusRoundTripsThroughTheWire) {
  const Report r = Sample();
  EXPECT_EQ(ThroughTheWire(r), r);
  EXPECT_FALSE(ThroughTheWire(r).has_running);  // no [running]: none in the status
}

// Running the bowel's score, with its events, its missed and damaged segments and its failed
// marks, through a status on the wire: the same report, exactly.
TEST(Report, StatusCarriesTheRunningScoreExactly) {
  Report r = Sample();
  r.has_running = true;
  // every field in RunningReport's order, none at its default: segments, their length,
  // coverage, missed, reversals, grasps, regrasps, slips, path, collisions, out of view, time;
  // the maxima; events, damaged; the estimate; the verdict; thresholds and pass marks
  // clang-format off
  r.running = {90, 0.05, 88.0 / 90.0, {12, 87}, 1, 21, 2, 1, 3.123456789, 4, 11.25, 33.3,
               20.0, 200000.0, 18.7, 33.1,
               {{"pinch", 9, "right", 16.27, 20.0}, {"traction", 19, "left", 31.5, 18.7}},
               {9, 19}, 0.95, 0.7, 0.357142857142857, false, {"estimate", "damage"},
               10.3, 300.0, 14.2, 1e-4, 1.0, 120.0, 20.0, 0.1, 1, 2, 3};
  // clang-format on
  const Report back = ThroughTheWire(r);
  EXPECT_TRUE(back.has_running);
  EXPECT_EQ(back, r);
  EXPECT_EQ(FormatReport(back), FormatReport(r));
}

TEST(Report, TextNamesEveryToolAndTarget) {
  const std::string text = FormatReport(Sample());
  for (const char* word : {"left", "right", "lesion", "hidden", "exposed at t = 2.00 s",
                           "not exposed yet", "traction events 2", "grasps 3 (regrasps 1)"}) {
    EXPECT_NE(text.find(word), std::string::npos) << word << " in\n" << text;
  }
}

}  // namespace
}  // namespace viscera::assessment
