// SPDX-License-Identifier: Apache-2.0
#include "framework/frame_geometry.h"

#include "framework/framework_error.h"

#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rbfmuscle {

namespace {

/// The numbers of a DataArray (named `name`, or the first one if `name` is empty) of `parent`.
std::vector<double> readArray(const tinyxml2::XMLElement* parent, const char* name, const std::string& path) {
  std::vector<double> values;
  if (!parent) return values;
  for (const tinyxml2::XMLElement* a = parent->FirstChildElement("DataArray"); a; a = a->NextSiblingElement("DataArray")) {
    const char* a_name = a->Attribute("Name");
    if (*name && !(a_name && std::string(a_name) == name)) continue;
    std::istringstream in(a->GetText() ? a->GetText() : "");
    double v;
    while (in >> v) values.push_back(v);
    if (!in.eof()) {
      throw FrameworkError(path + ": line " + std::to_string(a->GetLineNum()) + ": DataArray " +
                           (*name ? name : "of " + std::string(parent->Name())) + " holds a non-number");
    }
    return values;
  }
  return values;
}

}  // namespace

FrameGeometry readVtp(const std::string& path) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) {
    throw FrameworkError(path + ": cannot read as XML (" + std::string(doc.ErrorStr()) + ")");
  }
  const tinyxml2::XMLElement* vtk = doc.FirstChildElement("VTKFile");
  const tinyxml2::XMLElement* piece = vtk && vtk->FirstChildElement("PolyData")
                                          ? vtk->FirstChildElement("PolyData")->FirstChildElement("Piece")
                                          : nullptr;
  if (!piece) throw FrameworkError(path + ": expected VTKFile/PolyData/Piece");
  FrameGeometry g;
  g.name = std::filesystem::path(path).stem().string();
  const std::vector<double> points = readArray(piece->FirstChildElement("Points"), "", path);
  if (points.size() % 3 != 0) throw FrameworkError(path + ": " + std::to_string(points.size()) + " point coordinates, expected 3 per point");
  const long n = static_cast<long>(points.size() / 3);
  g.vertices_mm = Eigen::Map<const Eigen::Matrix3Xd>(points.data(), 3, n);
  const auto index = [&](double v) {
    if (!(v >= 0.0 && v < double(n)) || v != std::floor(v))
      throw FrameworkError(path + ": vertex index " + std::to_string(v) + " outside [0, " + std::to_string(n) + ")");
    return static_cast<int>(v);
  };
  const std::vector<double> polys = readArray(piece->FirstChildElement("Polys"), "connectivity", path);
  const std::vector<double> poly_offsets = readArray(piece->FirstChildElement("Polys"), "offsets", path);
  if (polys.size() != 3 * poly_offsets.size())
    throw FrameworkError(path + ": Polys hold " + std::to_string(polys.size()) + " indices for " +
                         std::to_string(poly_offsets.size()) + " polygons, expected triangles");
  g.triangles.resize(3, static_cast<Eigen::Index>(poly_offsets.size()));
  for (size_t i = 0; i < polys.size(); ++i) g.triangles(static_cast<Eigen::Index>(i % 3), static_cast<Eigen::Index>(i / 3)) = index(polys[i]);
  const std::vector<double> lines = readArray(piece->FirstChildElement("Lines"), "connectivity", path);
  const std::vector<double> line_offsets = readArray(piece->FirstChildElement("Lines"), "offsets", path);
  size_t start = 0;
  for (double end : line_offsets) {
    if (!(end >= double(start) && end <= double(lines.size())))
      throw FrameworkError(path + ": Lines offset " + std::to_string(end) + " outside [" + std::to_string(start) + ", " +
                           std::to_string(lines.size()) + "]");
    std::vector<int> line;
    for (size_t i = start; i < static_cast<size_t>(end); ++i) line.push_back(index(lines[i]));
    g.polylines.push_back(std::move(line));
    start = static_cast<size_t>(end);
  }
  return g;
}

void writeVtp(const std::string& path, const FrameGeometry& geometry) {
  const long n = geometry.vertices_mm.cols();
  auto check = [&](int index) {
    if (index < 0 || index >= n)
      throw FrameworkError("geometry '" + geometry.name + "': vertex index " +
                           std::to_string(index) + " outside [0, " + std::to_string(n) + ")");
  };
  for (long j = 0; j < geometry.triangles.cols(); ++j)
    for (int k = 0; k < 3; ++k) check(geometry.triangles(k, j));
  for (const auto& line : geometry.polylines)
    for (int index : line) check(index);

  std::ofstream out(path);
  if (!out) throw FrameworkError("cannot write " + path);
  out.precision(10);
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n"
      << "<Piece NumberOfPoints=\"" << n << "\" NumberOfVerts=\"0\" NumberOfLines=\""
      << geometry.polylines.size() << "\" NumberOfStrips=\"0\" NumberOfPolys=\""
      << geometry.triangles.cols() << "\">\n"
      << "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (long i = 0; i < n; ++i)
    out << geometry.vertices_mm(0, i) << ' ' << geometry.vertices_mm(1, i) << ' '
        << geometry.vertices_mm(2, i) << '\n';
  out << "</DataArray></Points>\n<Lines>\n"
      << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& line : geometry.polylines)
    for (int index : line) out << index << ' ';
  out << "\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  long offset = 0;
  for (const auto& line : geometry.polylines) out << (offset += static_cast<long>(line.size())) << ' ';
  out << "\n</DataArray>\n</Lines>\n<Polys>\n"
      << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (long j = 0; j < geometry.triangles.cols(); ++j)
    out << geometry.triangles(0, j) << ' ' << geometry.triangles(1, j) << ' '
        << geometry.triangles(2, j) << '\n';
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (long j = 0; j < geometry.triangles.cols(); ++j) out << 3 * (j + 1) << ' ';
  out << "\n</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
  if (!out) throw FrameworkError("cannot write " + path);
}

void PvdSeries::write(const std::string& path) const {
  std::ofstream out(path);
  if (!out) throw FrameworkError("cannot write " + path);
  out.precision(12);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const auto& entry : entries_)
    out << "  <DataSet timestep=\"" << entry.time_s << "\" part=\"0\" file=\"" << entry.file
        << "\"/>\n";
  out << "</Collection>\n</VTKFile>\n";
  if (!out) throw FrameworkError("cannot write " + path);
}

}  // namespace rbfmuscle
