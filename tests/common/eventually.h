#pragma once
// Eventually: wait for a condition by polling it, with a deadline, instead of sleeping a
// fixed time and hoping the system got there. A fixed sleep is too long on a quiet machine
// and too short on a busy one (ctest -j2 while someone builds); a poll is neither.
#include <chrono>
#include <functional>
#include <thread>

namespace viscera::testing {

/// Polls `done` until it returns true or `timeout_s` passes; between polls calls `wait`
/// (e.g. a bus pump that blocks up to a few ms), or sleeps 2 ms without one.
/// @return whether `done` became true. Use as ASSERT_TRUE(Eventually(...)) << "what".
template <typename Done>
bool Eventually(Done&& done, double timeout_s = 10.0, const std::function<void()>& wait = nullptr) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    if (wait) {
      wait();
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
  return true;
}

}  // namespace viscera::testing
