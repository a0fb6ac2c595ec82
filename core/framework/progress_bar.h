// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Progress of a run on stderr: frame i/N, frames/s and ETA. On a terminal the
/// line is redrawn at most every 0.1 s; otherwise a line is printed after the
/// first frame when the rest of the run is estimated to take kEstimateAfterSeconds
/// or more (the estimate), at 25 %, 50 %, 75 %, 100 %, when the run ends early,
/// and every kLogIntervalSeconds between those.
#include <chrono>

namespace rbfmuscle {

class ProgressBar {
 public:
  /// Longest time between two progress lines when stderr is not a terminal (s).
  static constexpr int kLogIntervalSeconds = 30;
  /// Remaining time from which the first frame's estimate is printed (s).
  static constexpr double kEstimateAfterSeconds = 10.0;

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
  int next_quarter_ = 0;  ///< 0: the first frame prints too, so a log shows when the loop started
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  int last_done_ = 0;
};

}  // namespace rbfmuscle
