// SPDX-License-Identifier: Apache-2.0
#include "framework/staged_directory.h"

#include "framework/framework_error.h"

#include <unistd.h>

#include <filesystem>

namespace rbfmuscle {

namespace fs = std::filesystem;

StagedDirectory::StagedDirectory(std::string target) : target_(std::move(target)) {
  fs::path path = fs::path(target_).lexically_normal();
  if (path.has_filename() == false) path = path.parent_path();
  std::error_code ec;
  if (fs::exists(path, ec)) {
    if (!fs::is_directory(path, ec))
      throw FrameworkError("output directory " + target_ + ": exists and is not a directory");
    if (!fs::is_empty(path, ec) && !fs::exists(path / "summary.json", ec))
      throw FrameworkError("output directory " + target_ +
                           ": exists, is not empty and is not an rbfmuscle output (no "
                           "summary.json); refusing to replace it");
  }
  target_path_ = fs::absolute(path).string();
  const fs::path parent = fs::absolute(path).parent_path();
  fs::create_directories(parent, ec);
  if (ec) throw FrameworkError("output directory " + target_ + ": cannot create " +
                               parent.string() + ": " + ec.message());
  staging_ = (parent / (path.filename().string() + ".partial-" + std::to_string(getpid()))).string();
  fs::remove_all(staging_, ec);
  if (!fs::create_directory(staging_, ec) || ec)
    throw FrameworkError("output directory " + target_ + ": cannot create " + staging_ + ": " +
                         ec.message());
  cleanup_ = std::make_unique<InterruptCleanup>(staging_);
}

StagedDirectory::~StagedDirectory() {
  if (committed_) return;
  if (isInterruptRequested() && isKeepPartialRequested()) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

void StagedDirectory::commit() {
  const fs::path path(target_path_);
  std::error_code ec;
  if (fs::exists(path, ec)) {
    fs::remove_all(path, ec);
    if (ec) throw FrameworkError("output directory " + target_ + ": cannot replace: " + ec.message());
  }
  fs::rename(staging_, path, ec);
  if (ec) throw FrameworkError("output directory " + target_ + ": cannot rename " + staging_ +
                               ": " + ec.message());
  committed_ = true;
}

}  // namespace rbfmuscle
