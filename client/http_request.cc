#include "client/http_request.h"

#include <string_view>

#include "common/check.h"

namespace viscera::client {
namespace {

// RFC 9110 token characters: what a method or a field name may hold.
bool IsToken(std::string_view text) {
  if (text.empty()) return false;
  for (char c : text) {
    const bool alnum = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
    if (!alnum && std::string_view("!#$%&'*+-.^_`|~").find(c) == std::string_view::npos)
      return false;
  }
  return true;
}

std::string_view Trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

// Splits off the next line, without its "\n" or "\r\n".
std::string_view NextLine(std::string_view* rest) {
  const size_t end = rest->find('\n');
  std::string_view line = rest->substr(0, end);
  rest->remove_prefix(end == std::string_view::npos ? rest->size() : end + 1);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

}  // namespace

size_t FindHeadEnd(const std::string& data) {
  const size_t crlf = data.find("\r\n\r\n");
  const size_t lf = data.find("\n\n");
  if (crlf == std::string::npos && lf == std::string::npos) return 0;
  if (lf == std::string::npos || (crlf != std::string::npos && crlf < lf)) return crlf + 4;
  return lf + 2;
}

std::string ParseHttpRequest(const std::string& head, HttpRequest* request) {
  VISCERA_DEMAND(request != nullptr);
  std::string_view rest(head);

  // request line: METHOD SP TARGET SP HTTP/1.x, single spaces
  const std::string_view line = NextLine(&rest);
  const size_t sp1 = line.find(' ');
  const size_t sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
  if (sp2 == std::string_view::npos || line.find(' ', sp2 + 1) != std::string_view::npos) {
    return "request line is not METHOD TARGET VERSION";
  }
  const std::string_view method = line.substr(0, sp1);
  const std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  const std::string_view version = line.substr(sp2 + 1);
  if (!IsToken(method)) return "bad method";
  if (target.empty() || target.front() != '/') return "target is not an absolute path";
  for (char c : target) {
    if (static_cast<unsigned char>(c) <= ' ' || c == 0x7f) return "control character in target";
  }
  if (version != "HTTP/1.0" && version != "HTTP/1.1") return "not HTTP/1.0 or HTTP/1.1";
  request->method = method;
  request->target = target;
  request->path = target.substr(0, target.find_first_of("?#"));
  request->version = version;

  // header fields, up to the blank line
  request->fields.clear();
  while (true) {
    if (rest.empty()) return "no blank line after the header fields";
    const std::string_view field = NextLine(&rest);
    if (field.empty()) break;
    const size_t colon = field.find(':');
    // no space before the colon, and no obsolete line folding (RFC 9112 section 5)
    if (colon == std::string_view::npos || !IsToken(field.substr(0, colon))) {
      return "malformed header field";
    }
    request->fields.emplace_back(field.substr(0, colon), Trim(field.substr(colon + 1)));
  }
  return "";
}

}  // namespace viscera::client
