#pragma once
/// Recorder: a session's record, an LCM log file (readable by lcm-logplayer and LCM's
/// LogFile API). Inputs (requests, poses as received, the exact per-step inputs) and
/// outputs (forces, skeletons, status) are written as they happen, from the I/O thread
/// and the mechanics thread alike (one mutex), and flushed to the kernel at least every
/// kFlushPeriodNs, so a crash of the server loses at most that much.
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "common/check.h"

namespace viscera::session {

class Recorder {
 public:
  /// Longest time written events may sit in the stdio buffer (ns).
  static constexpr int64_t kFlushPeriodNs = 50'000'000;

  /// Creates (truncates) `path`.
  /// @throws InputError when the file cannot be created.
  explicit Recorder(const std::string& path);
  /// Flushes and closes.
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// Appends `msg` (an lcm-gen type) as an event on `channel` stamped `utime` (µs, wall).
  /// Thread-safe; failures are counted, never thrown (the session must go on).
  template <typename Msg>
  void Write(const std::string& channel, const Msg& msg, int64_t utime);

  /// Raw bytes as received (for datagrams recorded before decoding). Thread-safe.
  void WriteRaw(const std::string& channel, const void* data, int size, int64_t utime);

  /// Pushes buffered events to the kernel now. Thread-safe.
  void Flush();

  const std::string& path() const { return path_; }
  int64_t events() const;
  /// Events or flushes that failed (a full disk): the record is missing what they held.
  int64_t failures() const;

 private:
  void WriteLocked(const std::string& channel, const void* data, int size, int64_t utime);

  std::string path_;
  mutable std::mutex mutex_;
  std::unique_ptr<lcm::LogFile> log_;
  std::vector<uint8_t> buffer_;
  int64_t last_flush_ns_ = 0;
  int64_t events_ = 0;
  int64_t failures_ = 0;
};

template <typename Msg>
void Recorder::Write(const std::string& channel, const Msg& msg, int64_t utime) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int size = msg.getEncodedSize();
  if (size < 0) {
    ++failures_;
    return;
  }
  buffer_.resize(static_cast<size_t>(size));
  if (msg.encode(buffer_.data(), 0, size) != size) {
    ++failures_;
    return;
  }
  WriteLocked(channel, buffer_.data(), size, utime);
}

}  // namespace viscera::session
