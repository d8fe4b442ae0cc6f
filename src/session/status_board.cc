#include "session/status_board.h"

namespace viscera::session {

using viscera_proto::session_status_t;

void StatusBoard::CountRejected(const std::string& why) {
  ++rejected_;
  SetError(why);
}

void StatusBoard::CountReplayed(const std::string& why) {
  ++replayed_;
  CountRejected(why);
}

void StatusBoard::SetError(const std::string& why) {
  std::lock_guard<std::mutex> lock(status_mutex_);
  last_error_ = why;
}

void StatusBoard::ReportFrames(const FrameStreamReport& report) {
  std::lock_guard<std::mutex> lock(frames_mutex_);
  frames_ = report;
}

session_status_t StatusBoard::Read() const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  {
    // never wait for the render thread: if it holds the lock, the last report read serves
    std::unique_lock<std::mutex> frames_lock(frames_mutex_, std::try_to_lock);
    if (frames_lock.owns_lock()) {
      if (frames_.error_serial != frames_seen_.error_serial) {
        last_error_ = frames_.error;  // a new render problem
      }
      frames_seen_ = frames_;
    }
  }
  session_status_t s = status_;
  s.state = state_.load();
  s.poses = poses_.load();
  s.rejected = rejected_.load();
  s.replayed = replayed_.load();
  s.last_error = last_error_;
  s.skin = frames_seen_.skin;
  s.frame_width = frames_seen_.width;
  s.frame_height = frames_seen_.height;
  s.frame_rate_hz = frames_seen_.rate_hz;
  s.achieved_frame_rate_hz = frames_seen_.achieved_rate_hz;
  s.frames = frames_seen_.frames;
  s.frames_dropped = frames_seen_.dropped;
  s.skin_ms = frames_seen_.skin_ms;
  s.render_ms = frames_seen_.render_ms;
  s.encode_ms = frames_seen_.encode_ms;
  s.frame_bytes = frames_seen_.frame_bytes;
  return s;
}

void StatusBoard::Post(session_status_t* status, int8_t new_state) {
  std::lock_guard<std::mutex> lock(status_mutex_);
  if (new_state >= 0) {
    state_ = new_state;
    status->state = new_state;
  }
  status_ = *status;
}

}  // namespace viscera::session
