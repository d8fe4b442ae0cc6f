#include "script/csv_rows.h"

#include <fstream>
#include <sstream>

#include "common/check.h"

namespace viscera::script {
namespace {

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  const size_t e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

}  // namespace

std::string ReadScriptFile(const std::string& path, const char* what) {
  std::ifstream in(path);
  ThrowUnless(in.good(), path, ": cannot open ", what);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void ForEachCsvRow(
    const std::string& text,
    const std::function<void(int line_no, const std::vector<std::string>& cells)>& row) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::vector<std::string> cells;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    cells.clear();
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(Trim(cell));
    row(line_no, cells);
  }
}

}  // namespace viscera::script
