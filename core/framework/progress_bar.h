#pragma once
/// @file
/// Progress of a run on stderr: frame i/N, frames/s and ETA. On a terminal the
/// line is redrawn at most every 0.1 s; otherwise at most five lines are
/// printed (at 25 %, 50 %, 75 %, 100 % and when the run ends early).
#include <chrono>

namespace rbfmuscle {

class ProgressBar {
 public:
  /// @param enabled false prints nothing
  ProgressBar(int total_frames, bool enabled);
  /// Reports that `done` frames are finished.
  void update(int done);
  /// Ends the line (terminal) after the last update.
  void finish();

 private:
  void print(int done, bool final_line);

  int total_;
  bool enabled_;
  bool terminal_;
  int next_quarter_ = 1;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  int last_done_ = 0;
};

}  // namespace rbfmuscle
