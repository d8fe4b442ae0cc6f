#pragma once
/// StopSignals: SIGINT and SIGTERM end a client command cleanly (a video gets its trailer, a
/// viewer its summary).
#include <signal.h>

namespace viscera::client {

/// Blocked on construction, before any thread starts (threads inherit the mask), and polled
/// between pumps. The mask stays: the command ends the process.
class StopSignals {
 public:
  StopSignals() {
    sigemptyset(&set_);
    sigaddset(&set_, SIGINT);
    sigaddset(&set_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set_, nullptr);
  }
  bool Received() const {
    const timespec zero{0, 0};
    return sigtimedwait(&set_, nullptr, &zero) > 0;
  }

 private:
  sigset_t set_;
};

}  // namespace viscera::client
