#include "framework/frame_geometry.h"

#include "framework/framework_error.h"

#include <fstream>

namespace rbfmuscle {

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
