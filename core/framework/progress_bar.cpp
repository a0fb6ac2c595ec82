// SPDX-License-Identifier: Apache-2.0
#include "framework/progress_bar.h"

#include <unistd.h>

#include <cstdio>

namespace rbfmuscle {

ProgressBar::ProgressBar(int total_frames, bool enabled)
    : total_(total_frames), enabled_(enabled && total_frames > 0),
      terminal_(isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

void ProgressBar::update(int done) {
  if (!enabled_) return;
  last_done_ = done;
  const auto now = std::chrono::steady_clock::now();
  if (terminal_) {
    if (done == total_ || now - last_draw_ >= std::chrono::milliseconds(100)) {
      last_draw_ = now;
      print(done, false);
    }
  } else if (next_quarter_ <= 4 && done * 4 >= next_quarter_ * total_) {
    while (next_quarter_ <= 4 && done * 4 >= next_quarter_ * total_) ++next_quarter_;
    last_draw_ = now;
    print(done, true);
  } else if ((done == 1 && std::chrono::duration<double>(now - start_).count() * (total_ - 1) >=
                              kEstimateAfterSeconds) ||
             now - last_draw_ >= std::chrono::seconds(kLogIntervalSeconds)) {
    // The first frame gives the estimate of a long run; slow runs report regularly.
    last_draw_ = now;
    print(done, true);
  }
}

void ProgressBar::finish() {
  if (!enabled_) return;
  if (terminal_) {
    print(last_done_, false);
    std::fputc('\n', stderr);
  } else if (last_done_ < total_) {
    print(last_done_, true);
  }
  std::fflush(stderr);
}

void ProgressBar::print(int done, bool final_line) {
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fps = elapsed_s > 0.0 ? done / elapsed_s : 0.0;
  const double eta_s = fps > 0.0 ? (total_ - done) / fps : 0.0;
  constexpr int kWidth = 30;
  const int filled = total_ > 0 ? kWidth * done / total_ : 0;
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  std::fprintf(stderr, "%s[%s] frame %d/%d  %.1f frames/s  ETA %.1f s%s", final_line ? "" : "\r",
               bar, done, total_, fps, eta_s, final_line ? "\n" : "   ");
  std::fflush(stderr);
}

}  // namespace rbfmuscle
