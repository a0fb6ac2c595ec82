// SPDX-License-Identifier: Apache-2.0
#include "geometry/vtp_arrays.h"

#include <zlib.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "geometry/mesh_error.h"

namespace rbfmuscle::detail::vtp {
namespace {

enum class Kind { kSigned, kUnsigned, kFloat };

struct ScalarType {
  const char* name;
  Kind kind;
  int size;  ///< bytes
};

constexpr ScalarType kScalarTypes[] = {
    {"Int8", Kind::kSigned, 1},    {"UInt8", Kind::kUnsigned, 1},  {"Int16", Kind::kSigned, 2},
    {"UInt16", Kind::kUnsigned, 2}, {"Int32", Kind::kSigned, 4},   {"UInt32", Kind::kUnsigned, 4},
    {"Int64", Kind::kSigned, 8},   {"UInt64", Kind::kUnsigned, 8}, {"Float32", Kind::kFloat, 4},
    {"Float64", Kind::kFloat, 8}};

/// A decoding fault; the caller adds the file, line and array.
class DecodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

int base64Value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/// The bytes of one binary array: raw bytes, or base64 text decoded on demand, four
/// characters at a time. A group ending in padding ends one base64 stream and the next group
/// starts another, so a header encoded apart from its data (as VTK writes compressed arrays)
/// decodes to the same bytes as one encoded together with its data.
class ByteSource {
 public:
  ByteSource(const char* begin, const char* end, bool base64) : pos_(begin), end_(end), base64_(base64) {
    if (base64_)
      for (const char* p = begin; p != end; ++p) chars_left_ += isSpace(*p) ? 0 : 1;
  }

  /// Makes at least `n` bytes available in bytes().
  /// @throws DecodeError when the source ends first or holds a character that is not base64.
  void need(std::uint64_t n) {
    if (n <= bytes_.size()) return;
    if (n > capacity()) throw DecodeError("needs " + std::to_string(n) + " bytes but holds only " + std::to_string(capacity()) + " (truncated or corrupt)");
    if (!base64_) {
      const std::size_t more = static_cast<std::size_t>(n - bytes_.size());
      bytes_.insert(bytes_.end(), pos_, pos_ + more);
      pos_ += more;
      return;
    }
    while (bytes_.size() < n) decodeGroup();
  }

  const std::vector<unsigned char>& bytes() const { return bytes_; }

  /// Most bytes the source can still give, counting those decoded already.
  std::uint64_t capacity() const {
    return bytes_.size() + (base64_ ? chars_left_ / 4 * 3 : static_cast<std::uint64_t>(end_ - pos_));
  }

  /// True when only white space is left (inline arrays must end with their data).
  bool atEnd() const {
    for (const char* p = pos_; p != end_; ++p)
      if (!isSpace(*p)) return false;
    return true;
  }

 private:
  void decodeGroup() {
    char c[4];
    int got = 0;
    while (got < 4 && pos_ != end_) {
      const char ch = *pos_++;
      if (isSpace(ch)) continue;
      c[got++] = ch;
      --chars_left_;
    }
    if (got == 0) throw DecodeError("base64 text ends before the data its header announces (truncated or corrupt)");
    if (got < 4) throw DecodeError("base64 text ends inside a 4-character group (truncated)");
    int v[4];
    int pad = 0;
    for (int i = 0; i < 4; ++i) {
      if (c[i] == '=' && i >= 2) {
        v[i] = 0;
        ++pad;
        continue;
      }
      if (pad > 0 || (v[i] = base64Value(c[i])) < 0)
        throw DecodeError(std::string("character '") + c[i] + "' is not base64");
    }
    const std::uint32_t bits = (std::uint32_t(v[0]) << 18) | (std::uint32_t(v[1]) << 12) |
                               (std::uint32_t(v[2]) << 6) | std::uint32_t(v[3]);
    bytes_.push_back(static_cast<unsigned char>(bits >> 16));
    if (pad < 2) bytes_.push_back(static_cast<unsigned char>((bits >> 8) & 0xff));
    if (pad < 1) bytes_.push_back(static_cast<unsigned char>(bits & 0xff));
  }

  const char* pos_;
  const char* end_;
  bool base64_;
  std::uint64_t chars_left_ = 0;  ///< base64: characters other than white space not yet decoded
  std::vector<unsigned char> bytes_;
};

/// Reads an unsigned integer of `size` bytes at `p` in the file's byte order.
std::uint64_t readUnsigned(const unsigned char* p, int size, bool big_endian) {
  std::uint64_t v = 0;
  for (int i = 0; i < size; ++i) {
    const int k = big_endian ? i : size - 1 - i;
    v = (v << 8) | p[k];
  }
  return v;
}

/// One value of `type` at `p`, as double (integers up to 2^53 exactly).
double readScalar(const unsigned char* p, const ScalarType& type, bool big_endian) {
  const std::uint64_t bits = readUnsigned(p, type.size, big_endian);
  switch (type.kind) {
    case Kind::kUnsigned:
      return static_cast<double>(bits);
    case Kind::kSigned: {
      const int shift = 64 - 8 * type.size;
      return static_cast<double>(static_cast<std::int64_t>(bits << shift) >> shift);
    }
    case Kind::kFloat:
      if (type.size == 4) {
        const std::uint32_t b32 = static_cast<std::uint32_t>(bits);
        float f;
        std::memcpy(&f, &b32, sizeof f);
        return f;
      } else {
        double d;
        std::memcpy(&d, &bits, sizeof d);
        return d;
      }
  }
  return 0.0;
}

/// The payload bytes of a binary array (header read, blocks inflated).
/// `expected_bytes` is the size the piece's counts require, or kUnknown.
std::vector<unsigned char> readPayload(ByteSource& src, const FileContext& f, std::uint64_t expected_bytes) {
  const int hb = f.header_bytes;
  const auto word = [&](std::size_t i) { return readUnsigned(src.bytes().data() + i * hb, hb, f.big_endian); };
  if (!f.compressed) {
    src.need(hb);
    const std::uint64_t n = word(0);
    if (expected_bytes != kUnknown && n != expected_bytes)
      throw DecodeError("header says " + std::to_string(n) + " bytes, the piece's counts need " +
                        std::to_string(expected_bytes));
    if (n > src.capacity() - hb)
      throw DecodeError("header says " + std::to_string(n) + " bytes but the array holds at most " +
                        std::to_string(src.capacity() - hb) + " (truncated file or corrupt header)");
    src.need(hb + n);
    return std::vector<unsigned char>(src.bytes().begin() + hb, src.bytes().begin() + hb + n);
  }

  // zlib header: number of blocks, block size, last block size (0: a full block), then the
  // compressed size of each block.
  src.need(3u * hb);
  const std::uint64_t blocks = word(0), block_size = word(1), last_size = word(2);
  if (blocks > (src.capacity() - 3u * hb) / hb)
    throw DecodeError("compression header says " + std::to_string(blocks) +
                      " blocks, more than the array can hold (counts beyond the file size)");
  src.need((3u + blocks) * hb);
  if (last_size > block_size)
    throw DecodeError("compression header sizes disagree: last block " + std::to_string(last_size) +
                      " bytes, larger than the block size " + std::to_string(block_size));
  const std::uint64_t header = (3u + blocks) * hb;
  std::uint64_t compressed_total = 0;
  for (std::uint64_t b = 0; b < blocks && compressed_total <= src.capacity(); ++b) {
    const std::uint64_t packed = word(3 + b);
    compressed_total = packed > src.capacity() ? src.capacity() + 1 : compressed_total + packed;
  }
  if (compressed_total > src.capacity() - header)
    throw DecodeError("compression header says " + std::to_string(compressed_total) +
                      " compressed bytes but the array holds at most " + std::to_string(src.capacity() - header) +
                      " (truncated file or corrupt header)");
  const auto block_raw = [&](std::uint64_t b) { return b + 1 == blocks && last_size != 0 ? last_size : block_size; };
  // Each block's claim is checked before anything is allocated.
  std::uint64_t raw_total = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t raw = block_raw(b), packed = word(3 + b);
    if (raw > kMaxInflateRatio * packed + 64)
      throw DecodeError("compression header says block " + std::to_string(b + 1) + " of " + std::to_string(blocks) +
                        " inflates from " + std::to_string(packed) + " to " + std::to_string(raw) +
                        " bytes, more than zlib can (corrupt header)");
    raw_total += raw;
  }
  if (expected_bytes != kUnknown && raw_total != expected_bytes)
    throw DecodeError("compression header sizes disagree with the piece: blocks inflate to " +
                      std::to_string(raw_total) + " bytes, the piece's counts need " + std::to_string(expected_bytes));
  src.need(header + compressed_total);
  std::vector<unsigned char> out(raw_total);
  std::uint64_t in_pos = header, out_pos = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t packed = word(3 + b);
    uLongf length = static_cast<uLongf>(block_raw(b));
    const int rc = ::uncompress(out.data() + out_pos, &length, src.bytes().data() + in_pos, static_cast<uLong>(packed));
    if (rc != Z_OK)
      throw DecodeError("compressed block " + std::to_string(b + 1) + " of " + std::to_string(blocks) +
                        " does not inflate (zlib: " + ::zError(rc) + "): corrupt compressed array");
    if (length != block_raw(b))
      throw DecodeError("compressed block " + std::to_string(b + 1) + " of " + std::to_string(blocks) + " inflates to " +
                        std::to_string(length) + " bytes, its header says " + std::to_string(block_raw(b)));
    in_pos += packed;
    out_pos += length;
  }
  return out;
}

const ScalarType* findScalarType(const char* name) {
  for (const ScalarType& t : kScalarTypes)
    if (name && std::strcmp(name, t.name) == 0) return &t;
  return nullptr;
}

/// The numbers of a format="ascii" array, separated by white space.
std::vector<double> readAsciiValues(const FileContext& f, const tinyxml2::XMLElement& array, const std::string& what,
                                    std::uint64_t expected_count) {
  const int line = array.GetLineNum();
  std::vector<double> values;
  const char* text = array.GetText();
  const char* p = text ? text : "";
  while (true) {
    while (isSpace(*p)) ++p;
    if (*p == '\0') break;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(p, &end);
    if (end == p) {
      std::string token;
      for (const char* q = p; *q && !isSpace(*q) && token.size() < 20; ++q) token += *q;
      fail(f, line, what + ": value " + std::to_string(values.size() + 1) + " ('" + token + "') is not a number");
    }
    values.push_back(v);
    p = end;
  }
  if (expected_count != kUnknown && values.size() != expected_count)
    fail(f, line, what + ": holds " + std::to_string(values.size()) + " values, the piece's counts need " +
                      std::to_string(expected_count));
  return values;
}

/// The payload bytes of a format="binary" (inline base64) or format="appended" array.
std::vector<unsigned char> readBinaryPayload(const FileContext& f, const tinyxml2::XMLElement& array,
                                             const std::string& what, const std::string& format,
                                             std::uint64_t expected_bytes) {
  const int line = array.GetLineNum();
  try {
    if (format == "binary") {
      const char* text = array.GetText();
      const char* begin = text ? text : "";
      ByteSource src(begin, begin + std::strlen(begin), true);
      std::vector<unsigned char> payload = readPayload(src, f, expected_bytes);
      if (!src.atEnd()) throw DecodeError("holds more data than its header says (header sizes disagree with the data)");
      return payload;
    }
    if (format == "appended") {
      if (!f.have_appended) fail(f, line, what + ": format=\"appended\" but the file has no <AppendedData>");
      const char* offset_attr = array.Attribute("offset");
      char* end = nullptr;
      const unsigned long long offset = offset_attr ? std::strtoull(offset_attr, &end, 10) : 0;
      if (!offset_attr || end == offset_attr || *end != '\0')
        fail(f, line, what + ": format=\"appended\" needs a numeric offset attribute");
      const std::uint64_t size = static_cast<std::uint64_t>(f.appended_end - f.appended_begin);
      if (offset > size)
        fail(f, line, what + ": offset " + std::to_string(offset) + " is beyond the appended data (" +
                          std::to_string(size) + " bytes; counts beyond the file size)");
      ByteSource src(f.appended_begin + offset, f.appended_end, !f.appended_raw);
      return readPayload(src, f, expected_bytes);
    }
    fail(f, line, what + ": format '" + format + "' is not supported (expected ascii, binary or appended)");
  } catch (const DecodeError& e) {
    fail(f, line, what + ": " + e.what());
  }
}

}  // namespace

[[noreturn]] void fail(const FileContext& f, int line, const std::string& what) {
  throw MeshError(f.path + (line > 0 ? ": line " + std::to_string(line) : std::string()) + ": " + what);
}

std::string describeArray(const tinyxml2::XMLElement& array, const char* owner) {
  const char* name = array.Attribute("Name");
  return std::string("DataArray ") + (name ? std::string("'") + name + "' " : std::string()) + "of " + owner;
}

std::vector<double> readArray(const FileContext& f, const tinyxml2::XMLElement& array, const char* owner,
                              std::uint64_t expected_count) {
  const int line = array.GetLineNum();
  const std::string what = describeArray(array, owner);
  const char* type_name = array.Attribute("type");
  const ScalarType* type = findScalarType(type_name);
  if (!type)
    fail(f, line, what + ": type '" + (type_name ? type_name : "") +
                      "' is not supported (expected Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, "
                      "Float32 or Float64)");
  const char* format_attr = array.Attribute("format");
  const std::string format = format_attr ? format_attr : "ascii";
  if (expected_count != kUnknown && expected_count > kMaxInflateRatio * f.file_size)
    fail(f, line, what + ": the piece's counts need " + std::to_string(expected_count) +
                      " values, more than a file of " + std::to_string(f.file_size) +
                      " bytes can hold (counts beyond the file size)");
  if (format == "ascii") return readAsciiValues(f, array, what, expected_count);

  const std::uint64_t expected_bytes = expected_count == kUnknown ? kUnknown : expected_count * type->size;
  const std::vector<unsigned char> payload = readBinaryPayload(f, array, what, format, expected_bytes);
  if (payload.size() % type->size != 0)
    fail(f, line, what + ": " + std::to_string(payload.size()) + " bytes is not a whole number of " + type->name +
                      " values");
  const std::size_t n = payload.size() / type->size;
  std::vector<double> values(n);
  for (std::size_t i = 0; i < n; ++i) values[i] = readScalar(payload.data() + i * type->size, *type, f.big_endian);
  return values;
}

}  // namespace rbfmuscle::detail::vtp
