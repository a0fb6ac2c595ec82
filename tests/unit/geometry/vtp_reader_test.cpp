// SPDX-License-Identifier: Apache-2.0
// The VTP reader: every encoding VTK writes (ASCII, inline base64, appended base64 and raw,
// zlib-compressed or not, UInt32/UInt64 headers, both byte orders), the project's own VTP writer,
// the OpenSim model's geometry, and the errors for corrupt, inconsistent and truncated files.
#include "geometry/vtp_reader.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "framework/frame_geometry.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::makeTempDir;
using test::modelPath;
using test::writeText;

template <typename F>
void expectMeshError(F f, std::initializer_list<std::string> parts) {
  try {
    f();
    FAIL() << "expected MeshError";
  } catch (const MeshError& e) {
    const std::string what = e.what();
    for (const auto& part : parts) EXPECT_NE(what.find(part), std::string::npos) << what << "\nmissing: " << part;
  }
}

// ---------------------------------------------------------------- a small VTK XML writer
// Written here from the VTK file-format description, independent of the reader.

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += n > 1 ? table[(v >> 6) & 63] : '=';
    out += n > 2 ? table[v & 63] : '=';
  }
  return out;
}

/// `value` as `size` bytes in the chosen byte order.
std::string bytesOf(std::uint64_t value, int size, bool big_endian) {
  std::string out(static_cast<std::size_t>(size), '\0');
  for (int i = 0; i < size; ++i)
    out[static_cast<std::size_t>(big_endian ? size - 1 - i : i)] = static_cast<char>((value >> (8 * i)) & 0xff);
  return out;
}

struct Encoding {
  std::string name;
  std::string format = "binary";    ///< ascii, binary, appended
  bool raw_appended = false;        ///< AppendedData encoding="raw"
  bool compressed = false;
  bool header64 = false;            ///< header_type="UInt64"
  bool big_endian = false;
  bool points64 = false;            ///< Float64 points, else Float32
  bool index64 = false;             ///< Int64 connectivity/offsets, else Int32
  std::size_t block_size = 32768;   ///< zlib block size
  int corrupt_block = -1;           ///< flip a byte inside this compressed block of the Points array
  long header_bytes_delta = 0;      ///< added to the Points array's declared (inflated) size
};

struct Cells {
  std::vector<std::vector<int>> polys, strips, lines;
};

class VtpWriter {
 public:
  explicit VtpWriter(Encoding e) : e_(std::move(e)) {}

  std::string write(const Eigen::Matrix3Xd& points, const Cells& cells) {
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\""
        << (e_.big_endian ? "BigEndian" : "LittleEndian") << "\" header_type=\"" << (e_.header64 ? "UInt64" : "UInt32")
        << "\"" << (e_.compressed ? " compressor=\"vtkZLibDataCompressor\"" : "") << ">\n<PolyData>\n"
        << "<Piece NumberOfPoints=\"" << points.cols() << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << cells.lines.size()
        << "\" NumberOfStrips=\"" << cells.strips.size() << "\" NumberOfPolys=\"" << cells.polys.size() << "\">\n";
    std::vector<double> xyz(points.data(), points.data() + points.size());
    xml << "<Points>" << array(e_.points64 ? "Float64" : "Float32", "", xyz, 3, true) << "</Points>\n";
    section(xml, "Lines", cells.lines);
    section(xml, "Strips", cells.strips);
    section(xml, "Polys", cells.polys);
    xml << "</Piece>\n</PolyData>\n";
    if (e_.format == "appended")
      xml << "<AppendedData encoding=\"" << (e_.raw_appended ? "raw" : "base64") << "\">\n   _" << appended_
          << "\n</AppendedData>\n";
    xml << "</VTKFile>\n";
    return xml.str();
  }

 private:
  void section(std::ostringstream& xml, const char* name, const std::vector<std::vector<int>>& cells) {
    if (cells.empty()) return;
    std::vector<double> conn, offsets;
    for (const auto& c : cells) {
      conn.insert(conn.end(), c.begin(), c.end());
      offsets.push_back(static_cast<double>(conn.size()));
    }
    const char* type = e_.index64 ? "Int64" : "Int32";
    xml << "<" << name << ">\n" << array(type, "connectivity", conn, 1, false)
        << array(type, "offsets", offsets, 1, false) << "</" << name << ">\n";
  }

  std::string array(const std::string& type, const std::string& name, const std::vector<double>& values,
                    int components, bool is_points) {
    std::ostringstream out;
    out << "<DataArray type=\"" << type << "\"" << (name.empty() ? "" : " Name=\"" + name + "\"")
        << " NumberOfComponents=\"" << components << "\" format=\"" << e_.format << "\"";
    if (e_.format == "ascii") {
      out << ">\n";
      out.precision(17);
      for (double v : values) out << v << ' ';
      out << "\n</DataArray>\n";
      return out.str();
    }
    std::string data;
    for (double v : values) {
      if (type == "Float32") {
        const float f = static_cast<float>(v);
        std::uint32_t bits;
        std::memcpy(&bits, &f, 4);
        data += bytesOf(bits, 4, e_.big_endian);
      } else if (type == "Float64") {
        std::uint64_t bits;
        std::memcpy(&bits, &v, 8);
        data += bytesOf(bits, 8, e_.big_endian);
      } else {
        data += bytesOf(static_cast<std::uint64_t>(static_cast<std::int64_t>(v)), type == "Int64" ? 8 : 4, e_.big_endian);
      }
    }
    const int hb = e_.header64 ? 8 : 4;
    std::string header, payload;
    if (!e_.compressed) {
      header = bytesOf(data.size() + (is_points ? e_.header_bytes_delta : 0), hb, e_.big_endian);
      payload = data;
    } else {
      std::vector<std::string> blocks;
      for (std::size_t i = 0; i < data.size(); i += e_.block_size) {
        const std::string raw = data.substr(i, e_.block_size);
        uLongf length = compressBound(raw.size());
        std::string packed(length, '\0');
        EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(&packed[0]), &length,
                            reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 9), Z_OK);
        packed.resize(length);
        if (is_points && e_.corrupt_block == static_cast<int>(blocks.size())) packed[packed.size() / 2] ^= 0x5a;
        blocks.push_back(packed);
      }
      const std::size_t last = data.size() % e_.block_size;
      header = bytesOf(blocks.size(), hb, e_.big_endian) + bytesOf(e_.block_size, hb, e_.big_endian) +
               bytesOf(last + (is_points ? e_.header_bytes_delta : 0), hb, e_.big_endian);
      for (const auto& b : blocks) header += bytesOf(b.size(), hb, e_.big_endian);
      for (const auto& b : blocks) payload += b;
    }
    // VTK encodes a compressed array's header apart from its data, and an uncompressed array's
    // header together with it.
    const std::string encoded = e_.compressed ? base64(header) + base64(payload) : base64(header + payload);
    if (e_.format == "binary") {
      out << ">\n" << encoded << "\n</DataArray>\n";
    } else {
      out << " offset=\"" << appended_.size() << "\"/>\n";
      appended_ += e_.raw_appended ? header + payload : encoded;
    }
    return out.str();
  }

  Encoding e_;
  std::string appended_;
};

/// Cube [10.25, 30.75]³ (exact in Float32) as six outward quads, and its 8 points.
Eigen::Matrix3Xd cubePoints() {
  Eigen::Matrix3Xd p(3, 8);
  for (int v = 0; v < 8; ++v) p.col(v) << 10.25 + 20.5 * (v & 1), 10.25 + 20.5 * ((v >> 1) & 1), 10.25 + 20.5 * ((v >> 2) & 1);
  return p;
}
Cells cubeCells() {
  Cells c;
  c.polys = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  c.lines = {{0, 7}, {1, 2, 3}};
  return c;
}

std::vector<Encoding> allEncodings() {
  std::vector<Encoding> list;
  auto add = [&](std::string name, auto&& set) {
    Encoding e;
    e.name = std::move(name);
    set(e);
    list.push_back(e);
  };
  add("ascii", [](Encoding& e) { e.format = "ascii"; });
  add("binary", [](Encoding&) {});
  add("binary_uint64_header_float64_int64", [](Encoding& e) { e.header64 = e.points64 = e.index64 = true; });
  add("binary_big_endian", [](Encoding& e) { e.big_endian = true; });
  add("zlib", [](Encoding& e) { e.compressed = true; });
  add("zlib_small_blocks", [](Encoding& e) { e.compressed = true; e.block_size = 20; });
  add("zlib_uint64_header_big_endian", [](Encoding& e) { e.compressed = e.header64 = e.big_endian = true; e.block_size = 16; });
  add("appended_base64", [](Encoding& e) { e.format = "appended"; });
  add("appended_base64_zlib", [](Encoding& e) { e.format = "appended"; e.compressed = true; e.block_size = 24; });
  add("appended_raw", [](Encoding& e) { e.format = "appended"; e.raw_appended = true; e.points64 = true; });
  add("appended_raw_zlib_uint64", [](Encoding& e) {
    e.format = "appended"; e.raw_appended = e.compressed = e.header64 = true; e.block_size = 32;
  });
  return list;
}

TEST(VtpReader, ReadsEveryEncodingAlike) {
  const auto dir = makeTempDir("vtp_encodings");
  const Eigen::Matrix3Xd points = cubePoints();
  const Cells cells = cubeCells();
  for (const Encoding& e : allEncodings()) {
    SCOPED_TRACE(e.name);
    const std::string path = writeText(dir / (e.name + ".vtp"), VtpWriter(e).write(points, cells));
    const VtpPolyData vtp = readVtpPolyData(path);
    EXPECT_EQ(vtp.points, points);
    EXPECT_EQ(vtp.polys, cells.polys);
    EXPECT_EQ(vtp.lines, cells.lines);
    EXPECT_TRUE(vtp.strips.empty());
    EXPECT_EQ(vtp.triangulate().cols(), 12);
    // loadMesh dispatches .vtp to the reader: a closed, outward cube of 20.5 mm.
    const TriangleMesh mesh = loadMesh(path);
    EXPECT_EQ(mesh.countVertices(), 8);
    EXPECT_EQ(mesh.countTriangles(), 12);
    EXPECT_DOUBLE_EQ(calcVolume(mesh), 20.5 * 20.5 * 20.5);
  }
}

TEST(VtpReader, TriangulatesPolygonsByFansAndStripsKeepingTheirWinding) {
  const auto dir = makeTempDir("vtp_strips");
  Eigen::Matrix3Xd points(3, 6);
  points << 0, 1, 0, 1, 0, 1,  //
      0, 0, 1, 1, 2, 2,        //
      0, 0, 0, 0, 0, 0;
  Cells cells;
  cells.strips = {{0, 1, 2, 3, 4, 5}};
  cells.polys = {{0, 1, 3, 2}};
  Encoding e;
  e.compressed = true;
  const VtpPolyData vtp = readVtpPolyData(writeText(dir / "strip.vtp", VtpWriter(e).write(points, cells)));
  Eigen::Matrix3Xi expected(3, 6);
  expected << 0, 0, 0, 2, 2, 4,  //
      1, 3, 1, 1, 3, 3,          //
      3, 2, 2, 3, 4, 5;
  EXPECT_EQ(vtp.triangulate(), expected);
  // every triangle of the strip faces +z, as the strip's first one does
  const Eigen::Matrix3Xi t = vtp.triangulate();
  for (Eigen::Index j = 0; j < t.cols(); ++j) {
    const Eigen::Vector3d n = (points.col(t(1, j)) - points.col(t(0, j))).cross(points.col(t(2, j)) - points.col(t(0, j)));
    EXPECT_GT(n.z(), 0.0) << "triangle " << j;
  }
}

// The project's VTP writer (ASCII, per-frame surfaces and fibres) → this reader.
TEST(VtpReader, ReadsWhatTheFrameGeometryWriterWrites) {
  const auto dir = makeTempDir("vtp_round_trip");
  FrameGeometry g;
  g.name = "muscle";
  const TriangleMesh sphere = test::makeIcosphere(37.5, 2);
  g.vertices_mm = sphere.vertices_mm;
  g.vertices_mm.row(0).array() += 143.225;  // CT-like coordinates
  g.vertices_mm.row(2).array() -= 432.499;
  g.triangles = sphere.triangles;
  g.polylines = {{0, 5, 9}, {3, 4}};
  const std::string path = (dir / "muscle.vtp").string();
  writeVtp(path, g);
  const VtpPolyData vtp = readVtpPolyData(path);
  ASSERT_EQ(vtp.points.cols(), g.vertices_mm.cols());
  EXPECT_LE((vtp.points - g.vertices_mm).cwiseAbs().maxCoeff(), 1e-6);  // 10 significant digits
  EXPECT_EQ(vtp.triangulate(), g.triangles);
  EXPECT_EQ(vtp.lines, g.polylines);
  const TriangleMesh mesh = loadMesh(path);
  EXPECT_EQ(mesh.countTriangles(), g.triangles.cols());
  EXPECT_NEAR(calcVolume(mesh), calcVolume(sphere), 1e-6 * calcVolume(sphere));
}

// The OpenSim model's geometry: zlib-compressed inline base64 arrays (Float32 points, Int32 cells).
TEST(VtpReader, ReadsTheOpenSimModelGeometry) {
  const VtpPolyData femur = readVtpPolyData(modelPath("hip/osim/geometry/LHDL_femur_r.vtp"));
  EXPECT_EQ(femur.points.cols(), 42502);
  EXPECT_EQ(femur.polys.size(), 84998u);
  const LoadedMesh femur_mesh = readMesh(modelPath("hip/osim/geometry/LHDL_femur_r.vtp"));
  EXPECT_EQ(femur_mesh.mesh.countTriangles(), 84998);
  // the same bone as models/hip/meshes/femur_r.ply (530.2 ml), in the same CT frame (mm)
  EXPECT_NEAR(calcVolume(femur_mesh.mesh) / 1000.0, 530.2, 0.1);
  const Eigen::AlignedBox3d box = femur_mesh.mesh.calcBoundingBox();
  const Eigen::AlignedBox3d ply_box = loadMesh(modelPath("hip/meshes/femur_r.ply")).calcBoundingBox();
  EXPECT_LE((box.min() - ply_box.min()).cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LE((box.max() - ply_box.max()).cwiseAbs().maxCoeff(), 0.1);

  const VtpPolyData pelvis = readVtpPolyData(modelPath("hip/osim/geometry/LHDL_pelvis.vtp"));
  EXPECT_EQ(pelvis.points.cols(), 134945);
  EXPECT_EQ(pelvis.polys.size(), 269966u);
  // right ilium + sacrum + left ilium: 346.5 + 245.7 + 364.0 ml (models/hip/README.md)
  const LoadedMesh pelvis_mesh = readMesh(modelPath("hip/osim/geometry/LHDL_pelvis.vtp"));
  EXPECT_NEAR(calcVolume(pelvis_mesh.mesh) / 1000.0, 956.3, 0.2);
}

TEST(VtpReader, CorruptCompressedArrayIsNamed) {
  const auto dir = makeTempDir("vtp_corrupt");
  Encoding e;
  e.compressed = true;
  e.block_size = 48;
  e.corrupt_block = 1;
  const std::string path = writeText(dir / "corrupt.vtp", VtpWriter(e).write(cubePoints(), cubeCells()));
  expectMeshError([&] { readVtpPolyData(path); },
                  {path + ": line 5: DataArray of Points: compressed block 2 of 2 does not inflate (zlib:",
                   "corrupt compressed array"});
  expectMeshError([&] { loadMesh(path); }, {path, "corrupt compressed array"});
}

TEST(VtpReader, HeaderSizesThatDisagreeAreNamed) {
  const auto dir = makeTempDir("vtp_sizes");
  Encoding e;
  e.compressed = true;
  e.header_bytes_delta = 8;  // last block said to inflate to 8 bytes more than it does
  std::string path = writeText(dir / "zlib_sizes.vtp", VtpWriter(e).write(cubePoints(), cubeCells()));
  expectMeshError([&] { readVtpPolyData(path); },
                  {path + ": line 5: DataArray of Points: compression header sizes disagree with the piece: blocks "
                          "inflate to 104 bytes, the piece's counts need 96"});
  e.compressed = false;
  path = writeText(dir / "plain_sizes.vtp", VtpWriter(e).write(cubePoints(), cubeCells()));
  expectMeshError([&] { readVtpPolyData(path); },
                  {path + ": line 5: DataArray of Points: header says 104 bytes, the piece's counts need 96"});
  // a header claiming far more than the array holds (the piece's count agreeing with it)
  std::string text = VtpWriter(Encoding{}).write(cubePoints(), cubeCells());
  text.replace(text.find("NumberOfPoints=\"8\""), 18, "NumberOfPoints=\"9\"");
  path = writeText(dir / "count_sizes.vtp", text);
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line 5: DataArray of Points: header says 96 bytes, the piece's counts need 108"});
}

TEST(VtpReader, CountsBeyondTheFileSizeAreRefusedBeforeAllocating) {
  const auto dir = makeTempDir("vtp_counts");
  std::string text = VtpWriter(Encoding{}).write(cubePoints(), cubeCells());
  text.replace(text.find("NumberOfPoints=\"8\""), 18, "NumberOfPoints=\"4000000000\"");
  std::string path = writeText(dir / "huge_count.vtp", text);
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line 4: <Piece> NumberOfPoints=4000000000", "counts beyond the file size"});

  // a compressed header claiming 2^40 compressed bytes
  Encoding e;
  e.compressed = true;
  e.header64 = true;
  text = VtpWriter(e).write(cubePoints(), cubeCells());
  const std::size_t start = text.find("format=\"binary\">\n") + 17;
  const std::string huge_header = base64(bytesOf(1, 8, false) + bytesOf(32768, 8, false) + bytesOf(96, 8, false) +
                                         bytesOf(std::uint64_t(1) << 40, 8, false));
  text.replace(start, huge_header.size(), huge_header);
  path = writeText(dir / "huge_block.vtp", text);
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line 5: DataArray of Points: compression header says", "compressed bytes but the array holds at most"});
}

// Found by fuzz_vtp: an ASCII offset of 1.1e33 was converted to an unsigned count before any
// bound was checked (undefined behaviour: the value fits no integer type).
TEST(VtpReader, AnOffsetBeyondAnyCountIsRefusedBeforeItBecomesOne) {
  const std::string path = std::string(RBFMUSCLE_SOURCE_DIR) + "/tests/unit/geometry/data/fuzz/offset_beyond_any_count.vtp";
  expectMeshError([&] { readVtpPolyData(path); },
                  {path + ": line 6: DataArray 'offsets' of Polys: offset 4 (", "is more than a file of 775 bytes can hold"});
}

// Found by fuzz_vtp: the appended data's start tag read as XML of another name
// (<AppendedDataDataArray ...>) left no <AppendedData> element, which was used unchecked.
TEST(VtpReader, AnAppendedTagOfAnotherNameIsRefused) {
  const std::string path = std::string(RBFMUSCLE_SOURCE_DIR) + "/tests/unit/geometry/data/fuzz/appended_tag_of_another_name.vtp";
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line ", "cannot read the <AppendedData> tag"});
}

TEST(VtpReader, TruncatedFilesAreNamed) {
  const auto dir = makeTempDir("vtp_truncated");
  std::string full;
  {
    std::ifstream in(modelPath("hip/osim/geometry/LHDL_femur_r.vtp"), std::ios::binary);
    full.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::string path = writeText(dir / "femur_cut.vtp", full.substr(0, full.size() * 6 / 10));
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line ", "not well-formed XML", "truncated or corrupt"});

  Encoding e;
  e.format = "appended";
  e.raw_appended = true;
  const std::string text = VtpWriter(e).write(cubePoints(), cubeCells());
  path = writeText(dir / "appended_cut.vtp", text.substr(0, text.size() - 60));
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line 17: <AppendedData> is not closed", "(truncated file)"});

  // base64 data cut short inside an inline array
  std::string cut = VtpWriter(Encoding{}).write(cubePoints(), cubeCells());
  const std::size_t data = cut.find("format=\"binary\">\n") + 17;
  cut.erase(data + 40, 60);
  path = writeText(dir / "inline_cut.vtp", cut);
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line 5: DataArray of Points: header says 96 bytes but the array holds at most 53"});
}

TEST(VtpReader, UnsupportedOrMalformedContentIsNamed) {
  const auto dir = makeTempDir("vtp_unsupported");
  std::string text = VtpWriter(Encoding{}).write(cubePoints(), cubeCells());
  std::string bad = text;
  bad.replace(bad.find("header_type=\"UInt32\""), 20, "compressor=\"vtkLZ4DataCompressor\"");
  std::string path = writeText(dir / "lz4.vtp", bad);
  expectMeshError([&] { readVtpPolyData(path); },
                  {path + ": line 2: compressor 'vtkLZ4DataCompressor' is not supported"});
  bad = text;
  bad[bad.find("format=\"binary\">\n") + 20] = '*';
  path = writeText(dir / "not_base64.vtp", bad);
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line 5: DataArray of Points: character '*' is not base64"});
  bad = text;
  bad.replace(bad.find("type=\"PolyData\""), 15, "type=\"UnstructuredGrid\"");
  path = writeText(dir / "grid.vtp", bad);
  expectMeshError([&] { readVtpPolyData(path); }, {path + ": line 2: VTKFile type is 'UnstructuredGrid', expected 'PolyData'"});
  Encoding ascii;
  ascii.format = "ascii";
  bad = VtpWriter(ascii).write(cubePoints(), cubeCells());
  const std::size_t polys = bad.find("Name=\"connectivity\"", bad.find("<Polys>"));
  const std::size_t digit = bad.find(">\n", polys) + 2;
  bad[digit] = '9';  // first polygon's first corner → point 9 of 8
  path = writeText(dir / "index.vtp", bad);
  expectMeshError([&] { readVtpPolyData(path); },
                  {path + ": line ", "DataArray 'connectivity' of Polys: value 1 (9", "is not a point index in [0, 8)"});
  expectMeshError([&] { readVtpPolyData((dir / "missing.vtp").string()); }, {"missing.vtp: cannot open VTP file"});
}

}  // namespace
}  // namespace rbfmuscle
