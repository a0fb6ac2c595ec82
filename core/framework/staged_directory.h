// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Output directory written all-or-nothing: files go to a staging directory
/// beside the target (`OUTDIR.partial-PID`), which commit() renames to OUTDIR.
/// Without commit() (an exception) the staging directory is removed, so a
/// failed run never leaves OUTDIR created or half-written. The staging directory is also
/// registered with InterruptCleanup, so a run ended by SIGINT or SIGTERM removes it too; with
/// --keep-partial (isKeepPartialRequested) an interrupted run keeps it for inspection.
#include <memory>
#include <string>

#include "framework/interrupt.h"

namespace rbfmuscle {

class StagedDirectory {
 public:
  /// Creates the staging directory (and OUTDIR's parent directories).
  /// @throws FrameworkError when OUTDIR exists and is not a directory, or
  ///   exists, is non-empty and holds no summary.json (it is not an earlier
  ///   rbfmuscle output, so it is never replaced), or when creation fails.
  explicit StagedDirectory(std::string target);
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;
  /// Removes the staging directory unless committed (or interrupted with --keep-partial).
  ~StagedDirectory();

  /// Where to write now.
  const std::string& getStagingPath() const { return staging_; }
  const std::string& getTargetPath() const { return target_; }
  /// Replaces OUTDIR (an earlier run's output is removed) by the staging directory.
  void commit();

 private:
  std::string target_;       ///< as given
  std::string target_path_;  ///< absolute, normalized, no trailing '/'
  std::string staging_;
  bool committed_ = false;
  std::unique_ptr<InterruptCleanup> cleanup_;
};

}  // namespace rbfmuscle
