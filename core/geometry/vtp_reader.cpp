// SPDX-License-Identifier: Apache-2.0
#include "geometry/vtp_reader.h"

#include <tinyxml2.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/file_checks.h"

namespace rbfmuscle {
namespace {

/// deflate cannot compress by more than about 1032:1, so a compressed-array header that claims
/// more inflated bytes than this many times its compressed bytes is corrupt (and would make the
/// reader allocate memory for data the file cannot hold).
constexpr std::uint64_t kMaxInflateRatio = 1032;

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

[[noreturn]] void fail(const FileContext& f, int line, const std::string& what) {
  throw MeshError(f.path + (line > 0 ? ": line " + std::to_string(line) : std::string()) + ": " + what);
}

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

constexpr std::uint64_t kUnknown = std::numeric_limits<std::uint64_t>::max();

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

std::string describeArray(const tinyxml2::XMLElement& array, const char* owner) {
  const char* name = array.Attribute("Name");
  return std::string("DataArray ") + (name ? std::string("'") + name + "' " : std::string()) + "of " + owner;
}

/// The values of one DataArray as doubles. `expected_count` is the number of values the piece's
/// counts require, or kUnknown.
std::vector<double> readArray(const FileContext& f, const tinyxml2::XMLElement& array, const char* owner,
                              std::uint64_t expected_count) {
  const int line = array.GetLineNum();
  const std::string what = describeArray(array, owner);
  const char* type_name = array.Attribute("type");
  const ScalarType* type = nullptr;
  for (const ScalarType& t : kScalarTypes)
    if (type_name && std::strcmp(type_name, t.name) == 0) type = &t;
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

  std::vector<double> values;
  if (format == "ascii") {
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

  std::vector<unsigned char> payload;
  const std::uint64_t expected_bytes = expected_count == kUnknown ? kUnknown : expected_count * type->size;
  try {
    if (format == "binary") {
      const char* text = array.GetText();
      const char* begin = text ? text : "";
      ByteSource src(begin, begin + std::strlen(begin), true);
      payload = readPayload(src, f, expected_bytes);
      if (!src.atEnd()) throw DecodeError("holds more data than its header says (header sizes disagree with the data)");
    } else if (format == "appended") {
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
      payload = readPayload(src, f, expected_bytes);
    } else {
      fail(f, line, what + ": format '" + format + "' is not supported (expected ascii, binary or appended)");
    }
  } catch (const DecodeError& e) {
    fail(f, line, what + ": " + e.what());
  }
  if (payload.size() % type->size != 0)
    fail(f, line, what + ": " + std::to_string(payload.size()) + " bytes is not a whole number of " + type->name +
                      " values");
  const std::size_t n = payload.size() / type->size;
  values.resize(n);
  for (std::size_t i = 0; i < n; ++i) values[i] = readScalar(payload.data() + i * type->size, *type, f.big_endian);
  return values;
}

const tinyxml2::XMLElement* findArray(const tinyxml2::XMLElement& parent, const char* name) {
  for (const tinyxml2::XMLElement* a = parent.FirstChildElement("DataArray"); a; a = a->NextSiblingElement("DataArray")) {
    const char* n = a->Attribute("Name");
    if (n && std::strcmp(n, name) == 0) return a;
  }
  return nullptr;
}

long countAttribute(const FileContext& f, const tinyxml2::XMLElement& piece, const char* name, bool required) {
  const char* text = piece.Attribute(name);
  if (!text) {
    if (required) fail(f, piece.GetLineNum(), std::string("<Piece> has no ") + name + " attribute");
    return 0;
  }
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text, &end, 10);
  if (end == text || *end != '\0' || errno != 0 || v < 0)
    fail(f, piece.GetLineNum(), std::string("<Piece> ") + name + "=\"" + text + "\": expected a count (a non-negative integer)");
  if (static_cast<unsigned long long>(v) > kMaxInflateRatio * f.file_size)
    fail(f, piece.GetLineNum(), std::string("<Piece> ") + name + "=" + text + " is more than a file of " +
                                    std::to_string(f.file_size) + " bytes can hold (counts beyond the file size)");
  return static_cast<long>(v);
}

/// Reads one cell section (Verts, Lines, Strips, Polys) of a piece with `count` cells over
/// `num_points` points whose indices start at `first_point` in the whole file.
std::vector<std::vector<int>> readCells(const FileContext& f, const tinyxml2::XMLElement& piece, const char* section,
                                        long count, long num_points, long first_point, int min_size) {
  std::vector<std::vector<int>> cells;
  if (count == 0) return cells;
  const tinyxml2::XMLElement* element = piece.FirstChildElement(section);
  if (!element)
    fail(f, piece.GetLineNum(), std::string("<Piece> says NumberOf") + section + "=" + std::to_string(count) +
                                    " but has no <" + section + "> element");
  const tinyxml2::XMLElement* offsets_xml = findArray(*element, "offsets");
  const tinyxml2::XMLElement* conn_xml = findArray(*element, "connectivity");
  if (!offsets_xml || !conn_xml)
    fail(f, element->GetLineNum(), std::string("<") + section + "> needs DataArrays named 'connectivity' and 'offsets'");
  std::vector<double> offsets = readArray(f, *offsets_xml, section, kUnknown);
  // VTK writes one end offset per cell; accept a leading 0 as well (n + 1 offsets).
  if (offsets.size() == static_cast<std::size_t>(count) + 1 && offsets.front() == 0.0) offsets.erase(offsets.begin());
  if (offsets.size() != static_cast<std::size_t>(count))
    fail(f, offsets_xml->GetLineNum(), describeArray(*offsets_xml, section) + ": holds " + std::to_string(offsets.size()) +
                                           " offsets, the piece says NumberOf" + section + "=" + std::to_string(count));
  double previous = 0.0;
  for (std::size_t c = 0; c < offsets.size(); ++c) {
    const double o = offsets[c];
    if (!(o >= previous) || o != std::floor(o))
      fail(f, offsets_xml->GetLineNum(), describeArray(*offsets_xml, section) + ": offset " + std::to_string(c + 1) + " (" +
                                             std::to_string(o) + ") is not an integer at least the previous one (" +
                                             std::to_string(previous) + ")");
    // Checked before it becomes a count: a double beyond any integer type would not convert.
    if (o > static_cast<double>(kMaxInflateRatio * f.file_size))
      fail(f, offsets_xml->GetLineNum(), describeArray(*offsets_xml, section) + ": offset " + std::to_string(c + 1) + " (" +
                                             std::to_string(o) + ") is more than a file of " +
                                             std::to_string(f.file_size) + " bytes can hold (counts beyond the file size)");
    previous = o;
  }
  const std::vector<double> conn = readArray(f, *conn_xml, section, static_cast<std::uint64_t>(previous));
  cells.reserve(static_cast<std::size_t>(count));
  std::size_t start = 0;
  for (std::size_t c = 0; c < offsets.size(); ++c) {
    const std::size_t end = static_cast<std::size_t>(offsets[c]);
    if (static_cast<int>(end - start) < min_size)
      fail(f, offsets_xml->GetLineNum(), std::string(section) + " cell " + std::to_string(c + 1) + " has " +
                                             std::to_string(end - start) + " vertices, expected at least " +
                                             std::to_string(min_size));
    std::vector<int> cell;
    cell.reserve(end - start);
    for (std::size_t i = start; i < end; ++i) {
      const double v = conn[i];
      if (!(v >= 0.0 && v < static_cast<double>(num_points)) || v != std::floor(v))
        fail(f, conn_xml->GetLineNum(), describeArray(*conn_xml, section) + ": value " + std::to_string(i + 1) + " (" +
                                            std::to_string(v) + ") is not a point index in [0, " +
                                            std::to_string(num_points) + ")");
      cell.push_back(static_cast<int>(first_point + static_cast<long>(v)));
    }
    cells.push_back(std::move(cell));
    start = end;
  }
  return cells;
}

int lineOf(const std::string& text, std::size_t pos) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
}

}  // namespace

Eigen::Matrix3Xi VtpPolyData::triangulate() const {
  std::vector<std::array<int, 3>> t;
  for (const auto& p : polys)
    for (std::size_t c = 2; c < p.size(); ++c) t.push_back({p[0], p[c - 1], p[c]});
  for (const auto& s : strips)
    for (std::size_t i = 0; i + 2 < s.size(); ++i)
      t.push_back(i % 2 == 0 ? std::array<int, 3>{s[i], s[i + 1], s[i + 2]}
                             : std::array<int, 3>{s[i + 1], s[i], s[i + 2]});
  Eigen::Matrix3Xi out(3, static_cast<Eigen::Index>(t.size()));
  for (std::size_t j = 0; j < t.size(); ++j)
    for (int k = 0; k < 3; ++k) out(k, static_cast<Eigen::Index>(j)) = t[j][static_cast<std::size_t>(k)];
  return out;
}

VtpPolyData readVtpPolyData(const std::string& path) {
  const std::string problem = io::findInputFileProblem(path, "a VTP file");
  if (problem.rfind("is ", 0) == 0) throw MeshError(path + ": " + problem);
  std::string text;
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw MeshError(path + ": cannot open VTP file (missing or unreadable)");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size <= 0) throw MeshError(path + ": the VTP file is empty");
    in.seekg(0, std::ios::beg);
    text.resize(static_cast<std::size_t>(size));
    if (!in.read(&text[0], size)) throw MeshError(path + ": read error");
  }
  return parseVtpPolyData(text, path);
}

VtpPolyData parseVtpPolyData(const std::string& text, const std::string& path) {
  FileContext f;
  f.path = path;
  if (text.empty()) throw MeshError(path + ": the VTP file is empty");
  f.file_size = text.size();

  // Appended data may be raw binary, which is not XML: parse only what comes before it and
  // keep the data as bytes.
  std::string xml = text;
  const std::size_t appended_tag = text.find("<AppendedData");
  std::string appended_element;
  if (appended_tag != std::string::npos) {
    f.have_appended = true;
    f.appended_line = lineOf(text, appended_tag);
    const std::size_t tag_end = text.find('>', appended_tag);
    const std::size_t marker = tag_end == std::string::npos ? std::string::npos : text.find('_', tag_end);
    const std::size_t close = text.rfind("</AppendedData>");
    if (marker == std::string::npos || close == std::string::npos || close < marker)
      fail(f, f.appended_line, "<AppendedData> is not closed by </AppendedData> after its '_' marker (truncated file)");
    appended_element = text.substr(appended_tag, tag_end + 1 - appended_tag) + "</AppendedData>";
    f.appended_begin = text.data() + marker + 1;
    f.appended_end = text.data() + close;
    xml = text.substr(0, appended_tag) + "</VTKFile>";
  }

  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
    fail(f, doc.ErrorLineNum(), std::string("not well-formed XML (") + doc.ErrorName() +
                                    "): the file is truncated or corrupt");
  const tinyxml2::XMLElement* vtk = doc.FirstChildElement("VTKFile");
  if (!vtk) fail(f, 0, "expected a <VTKFile> root element");
  const char* type = vtk->Attribute("type");
  if (!type || std::strcmp(type, "PolyData") != 0)
    fail(f, vtk->GetLineNum(), std::string("VTKFile type is '") + (type ? type : "") + "', expected 'PolyData'");
  if (const char* order = vtk->Attribute("byte_order")) {
    if (std::strcmp(order, "BigEndian") == 0) f.big_endian = true;
    else if (std::strcmp(order, "LittleEndian") != 0)
      fail(f, vtk->GetLineNum(), std::string("byte_order '") + order + "', expected LittleEndian or BigEndian");
  }
  if (const char* header = vtk->Attribute("header_type")) {
    if (std::strcmp(header, "UInt64") == 0) f.header_bytes = 8;
    else if (std::strcmp(header, "UInt32") != 0)
      fail(f, vtk->GetLineNum(), std::string("header_type '") + header + "', expected UInt32 or UInt64");
  }
  if (const char* compressor = vtk->Attribute("compressor")) {
    if (std::strcmp(compressor, "vtkZLibDataCompressor") == 0) f.compressed = true;
    else if (*compressor != '\0')
      fail(f, vtk->GetLineNum(), std::string("compressor '") + compressor +
                                     "' is not supported (expected vtkZLibDataCompressor or none)");
  }
  if (f.have_appended) {
    tinyxml2::XMLDocument tag;
    if (tag.Parse(appended_element.c_str()) != tinyxml2::XML_SUCCESS)
      fail(f, f.appended_line, "cannot read the <AppendedData> tag");
    const char* encoding = tag.FirstChildElement("AppendedData")->Attribute("encoding");
    if (encoding && std::strcmp(encoding, "raw") == 0) f.appended_raw = true;
    else if (!encoding || std::strcmp(encoding, "base64") != 0)
      fail(f, f.appended_line, std::string("AppendedData encoding '") + (encoding ? encoding : "") +
                                   "', expected base64 or raw");
  }
  const tinyxml2::XMLElement* poly = vtk->FirstChildElement("PolyData");
  if (!poly) fail(f, vtk->GetLineNum(), "<VTKFile type=\"PolyData\"> has no <PolyData> element");

  VtpPolyData out;
  std::vector<double> all_points;
  long first_point = 0;
  for (const tinyxml2::XMLElement* piece = poly->FirstChildElement("Piece"); piece;
       piece = piece->NextSiblingElement("Piece")) {
    const long n = countAttribute(f, *piece, "NumberOfPoints", true);
    const long n_verts = countAttribute(f, *piece, "NumberOfVerts", false);
    const long n_lines = countAttribute(f, *piece, "NumberOfLines", false);
    const long n_strips = countAttribute(f, *piece, "NumberOfStrips", false);
    const long n_polys = countAttribute(f, *piece, "NumberOfPolys", false);
    if (n > 0) {
      const tinyxml2::XMLElement* points = piece->FirstChildElement("Points");
      const tinyxml2::XMLElement* array = points ? points->FirstChildElement("DataArray") : nullptr;
      if (!array) fail(f, piece->GetLineNum(), "<Piece> has NumberOfPoints=" + std::to_string(n) + " but no <Points><DataArray>");
      const int components = array->IntAttribute("NumberOfComponents", 1);
      if (components != 3)
        fail(f, array->GetLineNum(), "DataArray of Points has NumberOfComponents=" + std::to_string(components) + ", expected 3");
      const std::vector<double> xyz = readArray(f, *array, "Points", 3u * static_cast<std::uint64_t>(n));
      for (std::size_t i = 0; i < xyz.size(); ++i)
        if (!std::isfinite(xyz[i]))
          fail(f, array->GetLineNum(), "point " + std::to_string(i / 3) + " has a non-finite coordinate");
      all_points.insert(all_points.end(), xyz.begin(), xyz.end());
    }
    out.verts += static_cast<long>(readCells(f, *piece, "Verts", n_verts, n, first_point, 1).size());
    for (auto& c : readCells(f, *piece, "Lines", n_lines, n, first_point, 2)) out.lines.push_back(std::move(c));
    for (auto& c : readCells(f, *piece, "Strips", n_strips, n, first_point, 3)) out.strips.push_back(std::move(c));
    for (auto& c : readCells(f, *piece, "Polys", n_polys, n, first_point, 3)) out.polys.push_back(std::move(c));
    first_point += n;
  }
  if (!poly->FirstChildElement("Piece")) fail(f, poly->GetLineNum(), "<PolyData> has no <Piece>");
  out.points = Eigen::Map<const Eigen::Matrix3Xd>(all_points.data(), 3, first_point);
  return out;
}

}  // namespace rbfmuscle
