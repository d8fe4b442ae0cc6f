#pragma once
/// ScrubbedRecord: what the server writes into a session's record of the messages it took,
/// always without their token and MAC (docs/security.md: a record may be shared).
#include <cstdint>
#include <string>

#include <viscera_proto/session_request_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "session/recorder.h"
#include "session/session_scene.h"

namespace viscera::server {

class ScrubbedRecord {
 public:
  /// A request of the session as it came (nothing without a recorder).
  void WriteRequest(session::Recorder* recorder, const viscera_proto::session_request_t& request,
                    int64_t utime);
  /// A pose of the session, on the channel it came on (nothing without a recorder).
  void WritePose(session::Recorder* recorder, const std::string& channel,
                 const viscera_proto::tool_pose_t& pose, int64_t utime);
  /// The create of session `session_id` as it came, and the scene as loaded with the rate in
  /// use: replay needs both.
  void WriteCreate(session::Recorder* recorder, const viscera_proto::session_request_t& request,
                   int64_t session_id, const session::SessionScene& scene, int64_t utime);

 private:
  // copies kept from message to message: a pose costs no allocation once they are grown
  viscera_proto::session_request_t request_{};
  viscera_proto::tool_pose_t pose_{};
};

}  // namespace viscera::server
