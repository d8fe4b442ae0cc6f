#pragma once
/// Text from the bus made safe to print on a terminal: a server (or anyone who can send on
/// the bus) chooses its ids, scene names and error messages, and an escape sequence in them
/// would reach the user's terminal.
#include <string>
#include <string_view>

namespace viscera::client {

/// `text` with control characters (C0, DEL, and C1 as UTF-8) shown as '?'; tabs and line
/// ends too, so that one field stays on one line.
inline std::string Printable(std::string_view text) {
  std::string out(text);
  for (size_t i = 0; i < out.size(); ++i) {
    const auto c = static_cast<unsigned char>(out[i]);
    if (c < 0x20 || c == 0x7F) out[i] = '?';
    // C1 controls (U+0080..U+009F, CSI among them) are 0xC2 0x80..0x9F in UTF-8
    if (c == 0xC2 && i + 1 < out.size() && static_cast<unsigned char>(out[i + 1]) >= 0x80 &&
        static_cast<unsigned char>(out[i + 1]) <= 0x9F) {
      out.replace(i, 2, "?");
    }
  }
  return out;
}

}  // namespace viscera::client
