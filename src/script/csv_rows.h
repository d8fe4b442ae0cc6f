#pragma once
/// The scripts' CSV: comma-separated cells, trimmed; blank lines and lines starting with `#`
/// skipped. Shared by the tool and camera scripts.
#include <functional>
#include <string>
#include <vector>

namespace viscera::script {

/// The text of a script file. @throws InputError "PATH: cannot open WHAT".
std::string ReadScriptFile(const std::string& path, const char* what);

/// Calls `row` with each line's number (from 1) and its trimmed cells, in order.
void ForEachCsvRow(
    const std::string& text,
    const std::function<void(int line_no, const std::vector<std::string>& cells)>& row);

}  // namespace viscera::script
