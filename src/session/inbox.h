#pragma once
/// Inbox: what the I/O thread hands to one session's mechanics thread. Latest pose wins
/// (one slot per tool); commands queue, bounded. Short critical sections under one mutex:
/// the I/O thread writes, the mechanics thread takes once per step.
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

#include "mechanics/tool.h"

namespace viscera::session {

/// A validated tool pose as the I/O thread received it.
struct PoseInput {
  mechanics::ToolTarget target;  ///< tip (m), unit orientation, jaw 0..1, active
  int64_t seq = -1;              ///< header.seq of the pose message
  int64_t client_utime = 0;      ///< header.utime: the client's send time (µs, wall)
  int64_t received_ns = 0;       ///< when it arrived (monotonic ns): drives the idle timeout
};

/// A command for the mechanics thread (from session_request_t). The camera is no command:
/// it never touches the mechanics (Session::SetCamera).
struct Command {
  enum class Kind { kReset, kPause, kResume };
  Kind kind = Kind::kReset;
};

class Inbox {
 public:
  /// Commands that may wait at once; more are refused (a client flooding commands).
  static constexpr size_t kMaxCommands = 64;

  /// @pre num_tools >= 0.
  explicit Inbox(int num_tools);

  int num_tools() const { return static_cast<int>(poses_.size()); }

  /// Keeps `pose` as tool's latest unless it is stale: neither its seq nor its client send
  /// time is newer than the pose held (a reordered or replayed datagram). A client that
  /// starts again from seq 0 is recognised by its newer send times.
  /// @pre 0 <= tool < num_tools(). @return false when stale (dropped).
  bool PostPose(int tool, const PoseInput& pose);

  /// Queues a command. @return false when kMaxCommands are already waiting.
  bool PostCommand(const Command& command);

  /// Copies every tool's latest pose into `poses` (resized once; no allocation after)
  /// and moves waiting commands into `commands` (cleared first). Mechanics thread.
  void Take(std::vector<PoseInput>* poses, std::vector<Command>* commands);

 private:
  std::mutex mutex_;
  std::vector<PoseInput> poses_;
  std::vector<Command> commands_;
};

}  // namespace viscera::session
