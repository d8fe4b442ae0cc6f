#include "session/recorder.h"

#include <cstdio>

#include "common/clock.h"

namespace viscera::session {

Recorder::Recorder(const std::string& path) : path_(path) {
  log_ = std::make_unique<lcm::LogFile>(path, "w");
  ThrowUnless(log_->good(), "cannot create session record '", path, "'");
  last_flush_ns_ = MonotonicNanos();
}

Recorder::~Recorder() { Flush(); }

void Recorder::WriteRaw(const std::string& channel, const void* data, int size, int64_t utime) {
  std::lock_guard<std::mutex> lock(mutex_);
  WriteLocked(channel, data, size, utime);
}

void Recorder::WriteLocked(const std::string& channel, const void* data, int size, int64_t utime) {
  lcm::LogEvent event;
  event.eventnum = 0;  // LCM numbers events itself
  event.timestamp = utime;
  event.channel = channel;
  event.datalen = size;
  event.data = const_cast<void*>(data);  // LogFile only reads it
  if (log_->writeEvent(&event) != 0) {
    ++failures_;
    return;
  }
  ++events_;
  const int64_t now = MonotonicNanos();
  if (now - last_flush_ns_ >= kFlushPeriodNs) {
    if (std::fflush(log_->getFilePtr()) != 0) ++failures_;  // a full disk shows here
    last_flush_ns_ = now;
  }
}

void Recorder::Flush() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (std::fflush(log_->getFilePtr()) != 0) ++failures_;
  last_flush_ns_ = MonotonicNanos();
}

int64_t Recorder::events() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return events_;
}

int64_t Recorder::failures() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failures_;
}

}  // namespace viscera::session
