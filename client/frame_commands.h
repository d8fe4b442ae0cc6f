#pragma once
/// The client's frame-stream commands: `viscera frames` (save JPEGs), `viscera record`
/// (a video through OpenCV's VideoWriter) and `viscera view` (MJPEG over HTTP for a
/// browser). Each listens to one session's VISCERA_FRAME_<id>; frames need no token.
#include <cstdint>
#include <memory>
#include <string>

#include "bus/message_auth.h"

namespace viscera::client {

struct FrameListenOptions {
  std::string url;                               ///< LCM URL (recv_buf_size is added)
  std::shared_ptr<const bus::MessageAuth> auth;  ///< nullptr: no MAC
  int64_t session_id = 0;
  int64_t count = 0;       ///< stop after this many frames; 0: no limit
  double seconds = 0.0;    ///< stop after this long; 0: no limit
  double timeout_s = 5.0;  ///< give up when no frame comes for this long
  bool json = false;       ///< print the summary as JSON
};

/// Exit codes shared with viscera_main: 0 done, 1 local error, 2 no frame came.
inline constexpr int kFramesOk = 0;
inline constexpr int kFramesLocalError = 1;
inline constexpr int kFramesNone = 2;

/// Saves frames as DIR/frame_000000.jpg, ... (the bytes as sent, not re-encoded).
int SaveFrames(const FrameListenOptions& options, const std::string& dir);

/// Writes the frames into a video (codec from the extension: .mp4 mp4v, .avi MJPG) at
/// `fps` frames per second (0: the session's frame rate, from its status). Frames lost on
/// the way or dropped by the server's renderer are filled with the previous picture, so
/// the video runs in real time.
int RecordVideo(const FrameListenOptions& options, const std::string& file, double fps);

/// `viscera view` (client/view_command.cc): serves the session on http://HOST:PORT/ until
/// SIGINT/SIGTERM, or `count` frames or `seconds` pass. With the session's scene (`scene_file`,
/// or "" for `scene_dir`/<the scene its status names>.toml) the page draws the session itself
/// from its skeleton stream; the server's frames stay on /stream.mjpg (the page's "server
/// frames"), and are all the page shows when the scene cannot be read (said on stderr).
int ViewOverHttp(const FrameListenOptions& options, const std::string& host_port,
                 const std::string& scene_file, const std::string& scene_dir);

}  // namespace viscera::client
