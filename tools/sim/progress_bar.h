#pragma once
/// A one-line progress bar on stderr, drawn only when stderr is a terminal.
#include <cstdint>

namespace viscera::tools {

class ProgressBar {
 public:
  explicit ProgressBar(int64_t total);
  ~ProgressBar();
  /// Redraws at most ~10 times a second.
  void Update(int64_t done);

 private:
  int64_t total_;
  int64_t last_draw_ns_ = 0;
  bool enabled_;
};

}  // namespace viscera::tools
