// SPDX-License-Identifier: Apache-2.0
#include "geometry/ply_reader.h"

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <utility>

#include "geometry/mesh_error.h"
#include "io/file_checks.h"

namespace rbfmuscle::detail {
namespace {

enum class Format { Ascii, BinaryLittle, BinaryBig };

struct Property {
  std::string name;
  std::string type;        ///< scalar type, or the item type of a list
  std::string count_type;  ///< empty unless this is a list
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
};

int sizeOf(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" ||
      type == "float" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

/// Sequential reader of the data section, ASCII or binary.
class BodyReader {
 public:
  BodyReader(const std::string& path, const std::string& data, std::size_t pos, Format format)
      : path_(path), data_(data), pos_(pos), format_(format) {}

  double read(const std::string& type) {
    if (format_ == Format::Ascii) return readAscii();
    const int n = sizeOf(type);
    if (pos_ + static_cast<std::size_t>(n) > data_.size())
      throw MeshError(path_ + ": PLY data ends early (truncated file)");
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    if (format_ == Format::BinaryBig)
      for (int i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    std::uint64_t u = 0;
    for (int i = n - 1; i >= 0; --i) u = (u << 8) | b[i];
    if (type == "float" || type == "float32") {
      float f;
      const std::uint32_t u32 = static_cast<std::uint32_t>(u);
      std::memcpy(&f, &u32, 4);
      return f;
    }
    if (n == 8) {
      double d;
      std::memcpy(&d, &u, 8);
      return d;
    }
    const bool is_signed = type[0] != 'u';
    if (is_signed && (u >> (8 * n - 1)) != 0) return double(std::int64_t(u) - (std::int64_t(1) << (8 * n)));
    return double(u);
  }

 private:
  double readAscii() {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    if (pos_ >= data_.size()) throw MeshError(path_ + ": PLY data ends early (truncated file)");
    const char* begin = data_.c_str() + pos_;
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    if (end == begin) {
      std::string token(begin, std::strcspn(begin, " \t\r\n"));
      throw MeshError(path_ + ": PLY data holds '" + token + "' where a number was expected");
    }
    pos_ += static_cast<std::size_t>(end - begin);
    return value;
  }

  const std::string& path_;
  const std::string& data_;
  std::size_t pos_;
  Format format_;
};

/// Fewest bytes one record of `e` takes in the data section: binary, the sizes of its
/// scalars and list counts (a list may be empty); ASCII, two characters per value and count
/// (a digit and a separator).
std::uintmax_t minRecordBytes(const Element& e, Format format) {
  std::uintmax_t bytes = 0;
  for (const Property& p : e.properties)
    bytes += format == Format::Ascii ? 2 : static_cast<std::uintmax_t>(sizeOf(p.count_type.empty() ? p.type : p.count_type));
  return bytes;
}

/// Refuses element counts the file cannot hold, before anything is allocated for them.
void checkCountsFitFile(const std::string& path, const std::vector<Element>& elements, Format format,
                        std::uintmax_t data_bytes) {
  std::uintmax_t left = data_bytes;
  bool has_vertex = false;
  for (const Element& e : elements) {
    if (e.name == "vertex") {
      has_vertex = true;
      bool axis[3] = {false, false, false};
      for (const Property& p : e.properties)
        if (p.count_type.empty() && p.name.size() == 1 && p.name[0] >= 'x' && p.name[0] <= 'z') axis[p.name[0] - 'x'] = true;
      if (!(axis[0] && axis[1] && axis[2]))
        throw MeshError(path + ": PLY element 'vertex' lacks scalar properties x, y and z");
    }
    if (e.count == 0) continue;
    const std::uintmax_t each = minRecordBytes(e, format);
    if (each == 0)
      throw MeshError(path + ": PLY element '" + e.name + "' declares " + std::to_string(e.count) +
                      " records but has no properties");
    if (!io::countFitsInBytes(e.count, each, left))
      throw MeshError(path + ": PLY header declares " + std::to_string(e.count) + " '" + e.name +
                      "' records of at least " + std::to_string(each) + " bytes each, but only " +
                      std::to_string(left) + " bytes of data are left in the file (truncated file or wrong count)");
    left -= static_cast<std::uintmax_t>(e.count) * each;
  }
  if (!has_vertex) throw MeshError(path + ": PLY header has no 'vertex' element");
}

/// What the header says: the data's format and its elements, and where the data begins.
struct PlyHeader {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t data_begin = 0;  ///< byte after the end_header line
};

/// Reads the header up to end_header. @throws MeshError naming the line when it is not understood.
PlyHeader readPlyHeader(const std::string& data, const std::string& path) {
  PlyHeader header;
  bool has_format = false;
  std::size_t pos = 0;
  int line_number = 0;
  for (;;) {
    const std::size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) throw MeshError(path + ": PLY header has no end_header line");
    std::string line = data.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    words >> key;
    const auto bad = [&](const std::string& why) {
      return MeshError(path + ": PLY header line " + std::to_string(line_number) + " '" + line +
                       "': " + why);
    };
    if (line_number == 1) {
      if (key != "ply") throw bad("expected 'ply'");
    } else if (key == "format") {
      std::string name;
      words >> name;
      if (name == "ascii") header.format = Format::Ascii;
      else if (name == "binary_little_endian") header.format = Format::BinaryLittle;
      else if (name == "binary_big_endian") header.format = Format::BinaryBig;
      else throw bad("unknown format");
      has_format = true;
    } else if (key == "element") {
      Element e;
      std::string count_text, extra;
      if (!(words >> e.name >> count_text) || (words >> extra)) throw bad("expected 'element NAME COUNT'");
      char* end = nullptr;
      e.count = std::strtoll(count_text.c_str(), &end, 10);
      if (*end != '\0' || e.count < 0 || e.count > kMaxPlyElementCount)
        throw bad("expected a whole number of records from 0 to " + std::to_string(kMaxPlyElementCount) +
                  ", got '" + count_text + "'");
      header.elements.push_back(e);
    } else if (key == "property") {
      if (header.elements.empty()) throw bad("property before any element");
      Property p;
      words >> p.type;
      if (p.type == "list") words >> p.count_type >> p.type;
      words >> p.name;
      if (p.name.empty() || sizeOf(p.type) == 0 ||
          (!p.count_type.empty() && sizeOf(p.count_type) == 0))
        throw bad("unknown property type");
      header.elements.back().properties.push_back(p);
    } else if (key == "end_header") {
      break;
    } else if (key != "comment" && key != "obj_info" && !key.empty()) {
      throw bad("unknown keyword");
    }
  }
  if (!has_format) throw MeshError(path + ": PLY header has no format line");
  header.data_begin = pos;
  return header;
}

/// Reads every element's records: the x, y, z of vertices and the vertex indices of faces are
/// kept, other properties read past.
PlyContent readPlyData(const std::string& data, const std::string& path, const PlyHeader& header) {
  PlyContent content;
  BodyReader body(path, data, header.data_begin, header.format);
  for (const Element& e : header.elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    if (is_vertex) content.vertices.resize(static_cast<std::size_t>(e.count), {0.0, 0.0, 0.0});
    for (long long i = 0; i < e.count; ++i) {
      for (const Property& p : e.properties) {
        if (p.count_type.empty()) {
          const double value = body.read(p.type);
          if (is_vertex && p.name.size() == 1 && p.name[0] >= 'x' && p.name[0] <= 'z')
            content.vertices[static_cast<std::size_t>(i)][static_cast<std::size_t>(p.name[0] - 'x')] = value;
          continue;
        }
        const double count = body.read(p.count_type);
        if (!(count >= 0)) throw MeshError(path + ": PLY list with negative length");
        const bool indices = is_face && (p.name == "vertex_indices" || p.name == "vertex_index");
        std::vector<int> face;
        for (double k = 0; k < count; ++k) {  // each read consumes data, so this ends with the file
          const double index = body.read(p.type);
          // Out-of-range values become -1, refused below with the face named.
          if (indices) face.push_back(index >= 0 && index <= 2147483647.0 ? int(index) : -1);
        }
        if (indices) content.faces.push_back(std::move(face));
      }
    }
  }
  return content;
}

/// Refuses a face whose vertex index is not one of the vertices, naming the face.
void checkFaceIndices(const std::string& path, const PlyContent& content) {
  const long long vertex_count = static_cast<long long>(content.vertices.size());
  for (std::size_t f = 0; f < content.faces.size(); ++f)
    for (int v : content.faces[f])
      if (v < 0 || v >= vertex_count)
        throw MeshError(path + ": PLY face " + std::to_string(f) + " uses vertex " +
                        std::to_string(v) + ", expected 0.." + std::to_string(vertex_count - 1));
}

}  // namespace

PlyContent readPly(const std::string& path) {
  const std::uintmax_t file_bytes = io::requireRegularFile<MeshError>(path, "a PLY mesh file");
  if (file_bytes > kMaxPlyFileBytes)
    throw MeshError(path + ": PLY file of " + std::to_string(file_bytes) + " bytes, more than the " +
                    std::to_string(kMaxPlyFileBytes) + " this reader accepts");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError(path + ": cannot open mesh file (missing or unreadable)");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parsePly(data, path);
}

PlyContent parsePly(const std::string& data, const std::string& path) {
  const PlyHeader header = readPlyHeader(data, path);
  checkCountsFitFile(path, header.elements, header.format, data.size() - header.data_begin);
  PlyContent content = readPlyData(data, path, header);
  checkFaceIndices(path, content);
  return content;
}

}  // namespace rbfmuscle::detail
