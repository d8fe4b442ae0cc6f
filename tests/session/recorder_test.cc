// A record on a full disk: the session goes on, the failures are counted (and reported in
// its status), never thrown.
#include "session/recorder.h"

#include <gtest/gtest.h>

#include <viscera_proto/session_status_t.hpp>

namespace viscera::session {
namespace {

TEST(Recorder, AFullDiskIsCountedNotThrown) {
  Recorder recorder("/dev/full");  // every write: ENOSPC
  viscera_proto::session_status_t status{};
  status.last_error = std::string(8192, 'x');  // past stdio's buffer
  for (int i = 0; i < 4; ++i) recorder.Write("STATUS", status, 1000 + i);
  recorder.Flush();
  EXPECT_GT(recorder.failures(), 0);
}

}  // namespace
}  // namespace viscera::session
