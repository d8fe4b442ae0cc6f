#pragma once
/// Bounds a scene's TOML text before the TOML parser sees it. toml++ builds one table per
/// level of a dotted key (`a.b.c = 1`) or table header (`[a.b.c]`) and recurses over them; an
/// 80 KB key 40,000 levels deep overflows a thread's stack. These limits are far above what a
/// scene needs (three levels) and far below what the parser survives.
#include <cstddef>
#include <string_view>

namespace viscera::scene {

struct TomlBounds {
  size_t max_bytes = 1 << 20;  ///< the whole text
  int max_key_depth = 16;      ///< parts of one dotted key or table header
  int max_bracket_depth = 32;  ///< arrays and inline tables open at once ([[x]] counts 2)
};

/// The limits scenes are read within (every path: network, file, fuzzer).
inline constexpr TomlBounds kSceneTomlBounds{};

/// Scans `text` lexically (strings, comments, brackets; no tables are built). A key's depth
/// is counted as the dots between two of `, = [ ] { }` or a line end, outside strings and
/// comments: exact for keys and headers, and a value adds at most one (a float or a time),
/// so nothing deeper can reach the parser.
/// @throws InputError naming the line, the depth found and the limit.
void CheckTomlBounds(std::string_view text, const TomlBounds& bounds = kSceneTomlBounds);

}  // namespace viscera::scene
