#pragma once
// How many session records a soak run must find (docs/reliability.md, "records").
#include <cstdint>

namespace viscera::soak {

/// One record per session the soak saw created, and at most one more per create it got no
/// answer to: under load a reply can be lost while the server made the session, which it
/// records when the session's lease ends.
constexpr bool RecordsAccountedFor(int64_t records, int64_t sessions_answered,
                                   int64_t creates_unanswered) {
  return records >= sessions_answered && records <= sessions_answered + creates_unanswered;
}

}  // namespace viscera::soak
