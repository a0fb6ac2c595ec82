// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to core/geometry: the DataArrays of a VTK XML file (vtp_reader.h) decoded to
/// numbers: ASCII text, or binary data, base64 or raw, inline or in <AppendedData>, uncompressed
/// or zlib-compressed in blocks, checked against what the file and the piece's counts allow.
#include <tinyxml2.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace rbfmuscle::detail::vtp {

/// deflate cannot compress by more than about 1032:1, so a compressed-array header that claims
/// more inflated bytes than this many times its compressed bytes is corrupt (and would make the
/// reader allocate memory for data the file cannot hold).
inline constexpr std::uint64_t kMaxInflateRatio = 1032;

/// A count that the piece does not fix (the array's own size is taken).
inline constexpr std::uint64_t kUnknown = std::numeric_limits<std::uint64_t>::max();

/// What the VTKFile element says about every binary array, and where appended data lies.
struct FileContext {
  std::string path;
  std::size_t file_size = 0;
  bool big_endian = false;
  int header_bytes = 4;     ///< UInt32 (default) or UInt64 header words
  bool compressed = false;  ///< compressor="vtkZLibDataCompressor"
  bool have_appended = false;
  bool appended_raw = false;
  int appended_line = 0;
  const char* appended_begin = nullptr;  ///< first byte after the '_' marker
  const char* appended_end = nullptr;    ///< the '<' of </AppendedData>
};

/// @throws MeshError "PATH: line N: what" (no line when `line` is 0).
[[noreturn]] void fail(const FileContext& f, int line, const std::string& what);

/// "DataArray 'NAME' of OWNER", as errors name an array.
std::string describeArray(const tinyxml2::XMLElement& array, const char* owner);

/// The values of one DataArray as doubles. `expected_count` is the number of values the piece's
/// counts require, or kUnknown.
/// @throws MeshError naming the file, the array's line and the array when its type, format or
///   encoding is not supported or its data is corrupt, truncated or disagrees with the counts.
std::vector<double> readArray(const FileContext& f, const tinyxml2::XMLElement& array, const char* owner,
                              std::uint64_t expected_count);

}  // namespace rbfmuscle::detail::vtp
