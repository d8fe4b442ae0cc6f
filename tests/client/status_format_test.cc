// viscera status's table: the running-the-bowel column.
#include "client/status_format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace viscera::client {
namespace {

using viscera_proto::session_status_t;

session_status_t Status(int64_t id, const std::string& scene) {
  session_status_t s{};
  s.header.session_id = id;
  s.scene = scene;
  s.state = session_status_t::kRunning;
  s.rate_hz = 100.0;
  s.achieved_rate_hz = 100.0;
  s.sim_time = 12.5;
  return s;
}

// A bowel-running session's status as the server fills it: 90 segments, `covered` of them.
session_status_t Running(int64_t id, int covered) {
  session_status_t s = Status(id, "bowel_run");
  s.running_segments = 90;
  s.running_coverage = covered / 90.0;
  return s;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The text of `line` under the header's `column` (right-aligned: the same last character).
std::string Under(const std::string& header, const std::string& line, const std::string& column,
                  size_t width) {
  const size_t end = header.find(column) + column.size();
  return line.substr(end - width, width);
}

TEST(StatusTable, ARunningSessionShowsItsCoverageInTheRunningColumn) {
  const std::vector<std::string> lines =
      Lines(StatusTable({Running(1, 80), Status(2, "cavity"), Running(3, 90)}));
  ASSERT_EQ(lines.size(), 4u);
  const std::string& header = lines[0];
  ASSERT_NE(header.find(" RUNNING "), std::string::npos) << header;
  EXPECT_LT(header.find("LEASE"), header.find("RUNNING"));
  EXPECT_LT(header.find("RUNNING"), header.find("LAST_ERROR"));
  EXPECT_EQ(Under(header, lines[1], "RUNNING", 8), "   88.9%") << lines[1];  // 80 of 90
  EXPECT_EQ(Under(header, lines[2], "RUNNING", 8), "       -") << lines[2];  // no [running]
  EXPECT_EQ(Under(header, lines[3], "RUNNING", 8), "  100.0%") << lines[3];
  // the columns after it stay under their headers
  session_status_t failed = Running(4, 0);
  failed.last_error = "boom";
  const std::vector<std::string> with_error = Lines(StatusTable({failed}));
  EXPECT_EQ(with_error[1].find("boom"), with_error[0].find("LAST_ERROR")) << with_error[1];
  EXPECT_EQ(Under(with_error[0], with_error[1], "RUNNING", 8), "    0.0%");
}

TEST(StatusTable, WithoutARunningSessionTheTableHasNoRunningColumn) {
  const std::string table = StatusTable({Status(1, "cavity"), Status(2, "hanging")});
  EXPECT_EQ(table.find("RUNNING"), std::string::npos) << table;
  const std::vector<std::string> lines = Lines(table);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].substr(lines[0].find("LEASE")), "LEASE  LAST_ERROR");
  // the lease column (none: "-") is followed by the error column, two spaces apart
  EXPECT_EQ(lines[1].substr(lines[1].size() - 3), "-  ") << lines[1];
}

TEST(StatusTable, AHostileCoverageIsPrintedAsItIs) {
  session_status_t s = Running(1, 0);
  s.running_coverage = std::numeric_limits<double>::quiet_NaN();
  session_status_t huge = Running(2, 0);
  huge.running_coverage = 1e252;
  const std::vector<std::string> lines = Lines(StatusTable({s, huge}));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(Under(lines[0], lines[1], "RUNNING", 8), "     nan") << lines[1];
  EXPECT_EQ(Under(lines[0], lines[2], "RUNNING", 8), "  1e+254") << lines[2];
}

}  // namespace
}  // namespace viscera::client
