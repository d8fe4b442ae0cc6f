#include "sim/progress_bar.h"

#include <unistd.h>

#include <cstdio>

#include "common/clock.h"

namespace viscera::tools {

ProgressBar::ProgressBar(int64_t total)
    : total_(total > 0 ? total : 1), enabled_(isatty(STDERR_FILENO)) {}

ProgressBar::~ProgressBar() {
  if (enabled_) std::fprintf(stderr, "\r\033[K");
}

void ProgressBar::Update(int64_t done) {
  if (!enabled_) return;
  const int64_t now = MonotonicNanos();
  if (done < total_ && now - last_draw_ns_ < 100'000'000) return;
  last_draw_ns_ = now;
  constexpr int kWidth = 40;
  const int filled = static_cast<int>(kWidth * done / total_);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  std::fprintf(stderr, "\r[%s] %3d%%", bar, static_cast<int>(100 * done / total_));
  std::fflush(stderr);
}

}  // namespace viscera::tools
