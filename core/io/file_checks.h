// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Checks every reader and writer of the project makes on the paths it is given, header-only
/// so that each library (geometry, model, fit, framework, host) throws its own error type:
///
/// - an input is a regular file: a device (/dev/zero, /dev/urandom), a FIFO, a socket or a
///   directory is refused before it is opened, because reading one never ends or reads
///   nothing useful; the message names the file and what it is;
/// - an output is never the same file as an input: compared by device and inode (stat), so a
///   hard link, a symbolic link or another spelling of the same path is caught too, and by the
///   normalised absolute path when the output does not exist yet;
/// - an element count read from a file header is checked against the bytes the file has
///   left before anything is allocated for it.
#include <sys/stat.h>

#include <cstdint>
#include <filesystem>
#include <iterator>
#include <string>

namespace rbfmuscle::io {

/// What kind of file `mode` describes, e.g. "a character device".
inline std::string describeFileType(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISREG(mode)) return "a regular file";
  return "not a regular file";
}

/// Why `path` cannot be read as an input file, or "" when it is an existing regular file
/// (symbolic links are followed). `expected` says what the file should hold, e.g. "a mesh
/// file"; the text reads "is a character device, not a regular file (expected a mesh file)",
/// or for a missing file "cannot open it: no such file, or it cannot be reached (expected …)".
inline std::string findInputFileProblem(const std::string& path, const std::string& expected) {
  struct stat info {};
  if (path.empty()) return "is an empty path (expected " + expected + ")";
  if (::stat(path.c_str(), &info) != 0) return "cannot open it: no such file, or it cannot be reached (expected " + expected + ")";
  if (!S_ISREG(info.st_mode))
    return "is " + describeFileType(info.st_mode) + ", not a regular file (expected " + expected + ")";
  return "";
}

/// Throws Error("PATH: <problem>") unless `path` is an existing regular file; returns its
/// size in bytes.
template <class Error>
std::uintmax_t requireRegularFile(const std::string& path, const std::string& expected) {
  const std::string problem = findInputFileProblem(path, expected);
  if (!problem.empty()) throw Error(path + ": " + problem);
  struct stat info {};
  ::stat(path.c_str(), &info);
  return static_cast<std::uintmax_t>(info.st_size);
}

/// True when `a` and `b` name the same file: the same device and inode when both exist,
/// else the same normalised absolute path.
inline bool isSameFile(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path pa = fs::weakly_canonical(fs::absolute(a), ec);
  const fs::path pb = fs::weakly_canonical(fs::absolute(b), ec);
  return pa.lexically_normal() == pb.lexically_normal();
}

/// True when `path` is `directory` or lies inside it (both made absolute, normalised and with
/// symbolic links of their existing parts resolved).
inline bool isSameOrInside(const std::string& path, const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path), ec).lexically_normal();
  const fs::path d = fs::weakly_canonical(fs::absolute(directory), ec).lexically_normal();
  auto pi = p.begin();
  for (auto di = d.begin(); di != d.end(); ++di, ++pi) {
    if (di->empty() && std::next(di) == d.end()) break;  // trailing separator
    if (pi == p.end() || *pi != *di) return false;
  }
  return true;
}

/// True when `count` records of at least `min_bytes_each` bytes fit in `bytes_left`
/// (no overflow for any count).
inline bool countFitsInBytes(long long count, std::uintmax_t min_bytes_each, std::uintmax_t bytes_left) {
  if (count < 0) return false;
  if (min_bytes_each == 0) return true;
  return static_cast<std::uintmax_t>(count) <= bytes_left / min_bytes_each;
}

}  // namespace rbfmuscle::io
