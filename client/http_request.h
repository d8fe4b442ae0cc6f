#pragma once
/// The head of one HTTP/1.x request (request line and header fields), parsed strictly
/// enough to answer a browser, curl or a test; the MJPEG viewer needs nothing more.
#include <string>
#include <utility>
#include <vector>

namespace viscera::client {

/// Longest request head accepted (request line, fields and the blank line).
inline constexpr size_t kMaxRequestHead = 8 * 1024;

struct HttpRequest {
  std::string method;   ///< "GET", "HEAD", ... (case-sensitive, as RFC 9110 says)
  std::string target;   ///< as sent, e.g. "/stream.mjpg?t=1"
  std::string path;     ///< target up to any '?' or '#'
  std::string version;  ///< "HTTP/1.0" or "HTTP/1.1"
  std::vector<std::pair<std::string, std::string>> fields;  ///< name (as sent), value (trimmed)
};

/// Where the head ends in `data`: the offset just past the first blank line ("\r\n\r\n",
/// or a bare "\n\n" as some tools send), or 0 when no blank line has arrived yet.
size_t FindHeadEnd(const std::string& data);

/// Parses a request head (up to its blank line; anything after it is ignored).
/// @returns "" on success, else why the head is malformed (`request` is then unspecified).
std::string ParseHttpRequest(const std::string& head, HttpRequest* request);

}  // namespace viscera::client
