#pragma once
/// Building and checking viscera_proto::header_t, the header of every message.
#include <cstdint>
#include <string>

#include <viscera_proto/header_t.hpp>

namespace viscera::bus {

/// Wall-clock time now, in microseconds since the Unix epoch (the header's utime).
int64_t WallMicros();

/// This process's sender id (random, != 0, drawn once): the default header.sender.
int64_t ProcessSender();

/// A fresh random sender id (!= 0), for a client that keeps its own sequence counter.
int64_t NewSenderId();

/// A header of this build's protocol version, stamped now, from ProcessSender(), without a
/// token.
/// @pre seq >= 0.
viscera_proto::header_t MakeHeader(int64_t session_id, int64_t seq);

/// Why `header` cannot be accepted, or "" when it can: wrong version, negative
/// sequence, or a token count that disagrees with the token bytes.
std::string HeaderProblem(const viscera_proto::header_t& header);

}  // namespace viscera::bus
