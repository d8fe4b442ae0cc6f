// The MJPEG viewer's HTTP request-head parser (client/http_request.h): any bytes a browser
// or an attacker on the viewer's port may send.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "client/http_request.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const size_t end = viscera::client::FindHeadEnd(bytes);
  if (end > bytes.size()) std::abort();
  viscera::client::HttpRequest request;
  const std::string problem =
      viscera::client::ParseHttpRequest(end > 0 ? bytes.substr(0, end) : bytes, &request);
  if (problem.empty()) {
    // what a parsed request promises
    if (request.method.empty() || request.path.empty() || request.path[0] != '/') std::abort();
    if (request.version != "HTTP/1.0" && request.version != "HTTP/1.1") std::abort();
  }
  return 0;
}
