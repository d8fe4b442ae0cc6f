#include "bus/header.h"

#include <chrono>

#include "bus/message_auth.h"
#include "common/check.h"

namespace viscera::bus {

int64_t WallMicros() {
  using std::chrono::duration_cast;
  using std::chrono::microseconds;
  return duration_cast<microseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

int64_t NewSenderId() {
  const std::vector<uint8_t> r = RandomBytes(8);
  uint64_t v = 0;
  for (const uint8_t b : r) v = (v << 8) | b;
  return static_cast<int64_t>(v >> 1) | 1;  // positive, never 0
}

int64_t ProcessSender() {
  static const int64_t sender = NewSenderId();
  return sender;
}

viscera_proto::header_t MakeHeader(int64_t session_id, int64_t seq) {
  VISCERA_DEMAND(seq >= 0);
  viscera_proto::header_t header;
  header.version = viscera_proto::header_t::kProtocolVersion;
  header.session_id = session_id;
  header.seq = seq;
  header.utime = WallMicros();
  header.sender = ProcessSender();
  header.token_len = 0;
  header.mac_len = 0;
  return header;
}

std::string HeaderProblem(const viscera_proto::header_t& header) {
  if (header.version != viscera_proto::header_t::kProtocolVersion) {
    return Cat("protocol version ", header.version, " (this build speaks ",
               viscera_proto::header_t::kProtocolVersion, ")");
  }
  if (header.seq < 0) return Cat("negative sequence number ", header.seq);
  if (header.token_len < 0 || static_cast<size_t>(header.token_len) != header.token.size()) {
    return Cat("token_len ", header.token_len, " but ", header.token.size(), " token bytes");
  }
  if (header.mac_len < 0 || static_cast<size_t>(header.mac_len) != header.mac.size()) {
    return Cat("mac_len ", header.mac_len, " but ", header.mac.size(), " mac bytes");
  }
  return "";
}

}  // namespace viscera::bus
