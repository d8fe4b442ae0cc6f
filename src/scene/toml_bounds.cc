#include "scene/toml_bounds.h"

#include "common/check.h"

namespace viscera::scene {
namespace {

// The index just past the string that starts at `i` (a quote), counting its line ends into
// `line`. Basic strings take backslash escapes; literal strings do not. A single-line string
// stops at a line end (the parser refuses it there).
size_t SkipString(std::string_view t, size_t i, int* line) {
  const char q = t[i];
  const bool escapes = q == '"';
  const bool multi = t.substr(i, 3) == std::string_view(q == '"' ? "\"\"\"" : "'''");
  i += multi ? 3 : 1;
  while (i < t.size()) {
    const char c = t[i];
    if (escapes && c == '\\') {
      if (i + 1 < t.size() && t[i + 1] == '\n') ++*line;
      i += 2;
      continue;
    }
    if (c == '\n') {
      if (!multi) return i;
      ++*line;
    }
    if (c == q) {
      if (!multi) return i + 1;
      if (t.substr(i, 3) == std::string_view(q == '"' ? "\"\"\"" : "'''")) {
        i += 3;
        // up to two more quotes belong to the content ("""a""""" ends in two quotes)
        for (int extra = 0; extra < 2 && i < t.size() && t[i] == q; ++extra) ++i;
        return i;
      }
    }
    ++i;
  }
  return i;
}

}  // namespace

void CheckTomlBounds(std::string_view text, const TomlBounds& bounds) {
  ThrowUnless(text.size() <= bounds.max_bytes, "scene text of ", text.size(),
              " bytes: above the limit of ", bounds.max_bytes, " bytes");
  int line = 1;
  int dots = 0;      // since the last separator: a key's parts minus one
  int brackets = 0;  // [ and { open
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '"' || c == '\'') {
      i = SkipString(text, i, &line);
      continue;
    }
    if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
      continue;
    }
    switch (c) {
      case '.':
        ++dots;
        ThrowUnless(dots < bounds.max_key_depth, "line ", line,
                    ": a dotted key or [table] header nests deeper than ", "the limit of ",
                    bounds.max_key_depth, " levels");
        break;
      case '[':
      case '{':
        ++brackets;
        ThrowUnless(brackets <= bounds.max_bracket_depth, "line ", line,
                    ": arrays or inline tables nest deeper than the limit of ",
                    bounds.max_bracket_depth, " levels");
        dots = 0;
        break;
      case ']':
      case '}':
        if (brackets > 0) --brackets;
        dots = 0;
        break;
      case '\n':
        ++line;
        dots = 0;
        break;
      case ',':
      case '=': dots = 0; break;
      default: break;
    }
    ++i;
  }
}

}  // namespace viscera::scene
