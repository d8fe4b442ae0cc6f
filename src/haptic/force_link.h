#pragma once
/// ForceLink: how the device loop talks to the server, one tool of one session: poses out,
/// force answers in. LcmLink is the real one (lcm_link.h); tests may drive the loop with
/// their own. The network impairment sits in the loop, above this interface.
///
/// Threading: the device loop's thread calls everything.
#include <cstdint>
#include <functional>

#include "haptic/device.h"
#include "haptic/local_model.h"

namespace viscera::haptic {

class ForceLink {
 public:
  /// An answer and when it arrived (monotonic ns).
  using Sink = std::function<void(const Answer& answer, int64_t arrived_ns)>;

  virtual ~ForceLink() = default;
  /// Publishes the device's pose with sequence number `seq` (+1 per pose).
  virtual void SendPose(int64_t seq, const DeviceSample& sample) = 0;
  /// Hands every answer for the tool that arrived since the last call to `sink`, in arrival
  /// order. Never blocks.
  virtual void Poll(const Sink& sink) = 0;
  /// Messages dropped before becoming answers (another session or tool, bad header).
  virtual int64_t rejected() const = 0;
};

}  // namespace viscera::haptic
