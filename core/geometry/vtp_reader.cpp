// SPDX-License-Identifier: Apache-2.0
#include "geometry/vtp_reader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "geometry/vtp_arrays.h"
#include "io/file_checks.h"

namespace rbfmuscle {
namespace {

using detail::vtp::describeArray;
using detail::vtp::fail;
using detail::vtp::FileContext;
using detail::vtp::kMaxInflateRatio;
using detail::vtp::kUnknown;
using detail::vtp::readArray;

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

/// The XML part of the file. Appended data may be raw binary, which is not XML: only what comes
/// before it is parsed, and the data is kept as bytes (f.appended_begin … f.appended_end), its
/// start tag, closed, put in `appended_tag` for its attributes.
std::string splitOffAppendedData(const std::string& text, FileContext& f, std::string& appended_tag) {
  const std::size_t tag_begin = text.find("<AppendedData");
  if (tag_begin == std::string::npos) return text;
  f.have_appended = true;
  f.appended_line = lineOf(text, tag_begin);
  const std::size_t tag_end = text.find('>', tag_begin);
  const std::size_t marker = tag_end == std::string::npos ? std::string::npos : text.find('_', tag_end);
  const std::size_t close = text.rfind("</AppendedData>");
  if (marker == std::string::npos || close == std::string::npos || close < marker)
    fail(f, f.appended_line, "<AppendedData> is not closed by </AppendedData> after its '_' marker (truncated file)");
  appended_tag = text.substr(tag_begin, tag_end + 1 - tag_begin) + "</AppendedData>";
  f.appended_begin = text.data() + marker + 1;
  f.appended_end = text.data() + close;
  return text.substr(0, tag_begin) + "</VTKFile>";
}

/// The VTKFile element's type, byte order, header type and compressor, into `f`.
void readFileAttributes(const tinyxml2::XMLElement& vtk, FileContext& f) {
  const char* type = vtk.Attribute("type");
  if (!type || std::strcmp(type, "PolyData") != 0)
    fail(f, vtk.GetLineNum(), std::string("VTKFile type is '") + (type ? type : "") + "', expected 'PolyData'");
  if (const char* order = vtk.Attribute("byte_order")) {
    if (std::strcmp(order, "BigEndian") == 0) f.big_endian = true;
    else if (std::strcmp(order, "LittleEndian") != 0)
      fail(f, vtk.GetLineNum(), std::string("byte_order '") + order + "', expected LittleEndian or BigEndian");
  }
  if (const char* header = vtk.Attribute("header_type")) {
    if (std::strcmp(header, "UInt64") == 0) f.header_bytes = 8;
    else if (std::strcmp(header, "UInt32") != 0)
      fail(f, vtk.GetLineNum(), std::string("header_type '") + header + "', expected UInt32 or UInt64");
  }
  if (const char* compressor = vtk.Attribute("compressor")) {
    if (std::strcmp(compressor, "vtkZLibDataCompressor") == 0) f.compressed = true;
    else if (*compressor != '\0')
      fail(f, vtk.GetLineNum(), std::string("compressor '") + compressor +
                                    "' is not supported (expected vtkZLibDataCompressor or none)");
  }
}

/// The encoding of the appended data (base64 or raw), from its start tag, into `f`.
void readAppendedEncoding(const std::string& appended_tag, FileContext& f) {
  tinyxml2::XMLDocument tag;
  const tinyxml2::XMLElement* element =
      tag.Parse(appended_tag.c_str()) == tinyxml2::XML_SUCCESS ? tag.FirstChildElement("AppendedData") : nullptr;
  if (!element) fail(f, f.appended_line, "cannot read the <AppendedData> tag");
  const char* encoding = element->Attribute("encoding");
  if (encoding && std::strcmp(encoding, "raw") == 0) f.appended_raw = true;
  else if (!encoding || std::strcmp(encoding, "base64") != 0)
    fail(f, f.appended_line, std::string("AppendedData encoding '") + (encoding ? encoding : "") +
                                 "', expected base64 or raw");
}

/// The `count` points of a piece, appended to `all_points` as x, y, z.
void readPiecePoints(const FileContext& f, const tinyxml2::XMLElement& piece, long count,
                     std::vector<double>& all_points) {
  if (count <= 0) return;
  const tinyxml2::XMLElement* points = piece.FirstChildElement("Points");
  const tinyxml2::XMLElement* array = points ? points->FirstChildElement("DataArray") : nullptr;
  if (!array) fail(f, piece.GetLineNum(), "<Piece> has NumberOfPoints=" + std::to_string(count) + " but no <Points><DataArray>");
  const int components = array->IntAttribute("NumberOfComponents", 1);
  if (components != 3)
    fail(f, array->GetLineNum(), "DataArray of Points has NumberOfComponents=" + std::to_string(components) + ", expected 3");
  const std::vector<double> xyz = readArray(f, *array, "Points", 3u * static_cast<std::uint64_t>(count));
  for (std::size_t i = 0; i < xyz.size(); ++i)
    if (!std::isfinite(xyz[i]))
      fail(f, array->GetLineNum(), "point " + std::to_string(i / 3) + " has a non-finite coordinate");
  all_points.insert(all_points.end(), xyz.begin(), xyz.end());
}

/// Reads one piece into `out` and `all_points`, its point indices offset by `first_point`, the
/// number of points before it; returns its number of points.
long readPiece(const FileContext& f, const tinyxml2::XMLElement& piece, long first_point,
               std::vector<double>& all_points, VtpPolyData& out) {
  const long n = countAttribute(f, piece, "NumberOfPoints", true);
  const long n_verts = countAttribute(f, piece, "NumberOfVerts", false);
  const long n_lines = countAttribute(f, piece, "NumberOfLines", false);
  const long n_strips = countAttribute(f, piece, "NumberOfStrips", false);
  const long n_polys = countAttribute(f, piece, "NumberOfPolys", false);
  readPiecePoints(f, piece, n, all_points);
  out.verts += static_cast<long>(readCells(f, piece, "Verts", n_verts, n, first_point, 1).size());
  for (auto& c : readCells(f, piece, "Lines", n_lines, n, first_point, 2)) out.lines.push_back(std::move(c));
  for (auto& c : readCells(f, piece, "Strips", n_strips, n, first_point, 3)) out.strips.push_back(std::move(c));
  for (auto& c : readCells(f, piece, "Polys", n_polys, n, first_point, 3)) out.polys.push_back(std::move(c));
  return n;
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

  std::string appended_tag;
  const std::string xml = splitOffAppendedData(text, f, appended_tag);
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
    fail(f, doc.ErrorLineNum(), std::string("not well-formed XML (") + doc.ErrorName() +
                                    "): the file is truncated or corrupt");
  const tinyxml2::XMLElement* vtk = doc.FirstChildElement("VTKFile");
  if (!vtk) fail(f, 0, "expected a <VTKFile> root element");
  readFileAttributes(*vtk, f);
  if (f.have_appended) readAppendedEncoding(appended_tag, f);
  const tinyxml2::XMLElement* poly = vtk->FirstChildElement("PolyData");
  if (!poly) fail(f, vtk->GetLineNum(), "<VTKFile type=\"PolyData\"> has no <PolyData> element");

  VtpPolyData out;
  std::vector<double> all_points;
  long first_point = 0;
  for (const tinyxml2::XMLElement* piece = poly->FirstChildElement("Piece"); piece;
       piece = piece->NextSiblingElement("Piece"))
    first_point += readPiece(f, *piece, first_point, all_points, out);
  if (!poly->FirstChildElement("Piece")) fail(f, poly->GetLineNum(), "<PolyData> has no <Piece>");
  out.points = Eigen::Map<const Eigen::Matrix3Xd>(all_points.data(), 3, first_point);
  return out;
}

}  // namespace rbfmuscle
