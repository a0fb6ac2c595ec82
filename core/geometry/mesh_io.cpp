// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_io.h"

#include "geometry/ply_reader.h"
#include "io/file_checks.h"
#include "geometry/vtp_reader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>
#include <vector>

namespace rbfmuscle {
namespace {

using Point = std::array<double, 3>;

/// Raw import: every vertex of every mesh instance (transformed) and the triangles
/// indexing them.
struct RawMesh {
  std::vector<Point> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// Appends the meshes of `node` and its children, with accumulated transforms.
void collectTriangles(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent,
                      RawMesh& raw) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const int first = static_cast<int>(raw.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      raw.vertices.push_back({double(p.x), double(p.y), double(p.z)});
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      raw.triangles.push_back({first + int(face.mIndices[0]), first + int(face.mIndices[1]),
                               first + int(face.mIndices[2])});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c)
    collectTriangles(scene, *node.mChildren[c], transform, raw);
}

/// Welds referenced vertices with bit-identical coordinates, keeping the order of first
/// appearance in the vertex list (an indexed file without duplicates keeps its numbering).
/// `unused` receives the number of vertices no triangle references (dropped).
TriangleMesh weld(const RawMesh& raw, int& unused) {
  std::vector<char> referenced(raw.vertices.size(), 0);
  for (const auto& t : raw.triangles)
    for (int v : t) referenced[static_cast<std::size_t>(v)] = 1;
  unused = static_cast<int>(std::count(referenced.begin(), referenced.end(), 0));
  std::map<Point, int> index_of;
  std::vector<int> new_index(raw.vertices.size(), -1);
  std::vector<Point> unique;
  for (std::size_t v = 0; v < raw.vertices.size(); ++v) {
    if (!referenced[v]) continue;
    auto [it, inserted] = index_of.emplace(raw.vertices[v], static_cast<int>(unique.size()));
    if (inserted) unique.push_back(raw.vertices[v]);
    new_index[v] = it->second;
  }
  TriangleMesh mesh;
  mesh.vertices_mm.resize(3, static_cast<Eigen::Index>(unique.size()));
  for (std::size_t v = 0; v < unique.size(); ++v)
    for (int k = 0; k < 3; ++k) mesh.vertices_mm(k, static_cast<Eigen::Index>(v)) = unique[v][k];
  mesh.triangles.resize(3, static_cast<Eigen::Index>(raw.triangles.size()));
  for (std::size_t t = 0; t < raw.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      mesh.triangles(c, static_cast<Eigen::Index>(t)) =
          new_index[static_cast<std::size_t>(raw.triangles[t][static_cast<std::size_t>(c)])];
  return mesh;
}

void appendLittleEndian(std::string& out, std::uint64_t bits, int bytes) {
  for (int b = 0; b < bytes; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xffu));
}

/// Reads PLY with the reader of ply_reader.h; polygons are fan-triangulated.
RawMesh plyToRaw(detail::PlyContent ply) {
  RawMesh raw;
  raw.vertices = std::move(ply.vertices);
  for (const auto& face : ply.faces)
    for (std::size_t c = 2; c < face.size(); ++c) raw.triangles.push_back({face[0], face[c - 1], face[c]});
  return raw;
}

/// Reads any other format through assimp.
RawMesh readAssimpRaw(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  if (scene == nullptr)
    throw MeshError(path + ": cannot read mesh (assimp: " + importer.GetErrorString() + ")");
  // assimp readers can flag pure triangle meshes as polygonal (seen with PLY), and its
  // triangulation step then aborts on an internal assertion: recompute the flags from the faces and
  // triangulate only meshes that really hold polygons. Welding is done below on exact
  // positions, because assimp's JoinIdenticalVertices also compares normals and would
  // keep STL facets apart.
  bool has_polygons = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    aiMesh& mesh = *scene->mMeshes[m];
    unsigned types = 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const unsigned n = mesh.mFaces[f].mNumIndices;
      types |= n == 1   ? aiPrimitiveType_POINT
               : n == 2 ? aiPrimitiveType_LINE
               : n == 3 ? aiPrimitiveType_TRIANGLE
                        : aiPrimitiveType_POLYGON;
    }
    mesh.mPrimitiveTypes = types;
    has_polygons = has_polygons || (types & aiPrimitiveType_POLYGON) != 0;
  }
  if (has_polygons) {
    scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
    if (scene == nullptr)
      throw MeshError(path + ": cannot triangulate mesh (assimp: " + importer.GetErrorString() +
                      ")");
  }
  RawMesh raw;
  if (scene->mRootNode != nullptr) collectTriangles(*scene, *scene->mRootNode, aiMatrix4x4(), raw);
  return raw;
}

/// Reads VTK XML PolyData with the reader of vtp_reader.h (assimp has none); polygons and
/// strips are triangulated, lines and vertices ignored.
RawMesh vtpToRaw(const VtpPolyData& vtp) {
  RawMesh raw;
  raw.vertices.resize(static_cast<std::size_t>(vtp.points.cols()));
  for (Eigen::Index v = 0; v < vtp.points.cols(); ++v)
    raw.vertices[static_cast<std::size_t>(v)] = {vtp.points(0, v), vtp.points(1, v), vtp.points(2, v)};
  const Eigen::Matrix3Xi t = vtp.triangulate();
  raw.triangles.resize(static_cast<std::size_t>(t.cols()));
  for (Eigen::Index j = 0; j < t.cols(); ++j) raw.triangles[static_cast<std::size_t>(j)] = {t(0, j), t(1, j), t(2, j)};
  return raw;
}

/// True when `path` ends in `ext` (".ply"), ignoring case.
bool hasExtension(const std::string& path, const std::string& ext) {
  if (path.size() < ext.size()) return false;
  std::string tail = path.substr(path.size() - ext.size());
  for (char& ch : tail) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return tail == ext;
}

LoadedMesh finishMesh(const RawMesh& raw, const std::string& path);

}  // namespace

std::string LoadedMesh::describeDefects(const std::string& path) const {
  std::string text;
  if (unused_vertices > 0)
    text = std::to_string(unused_vertices) + (unused_vertices == 1 ? " unused vertex" : " unused vertices") +
           " dropped";
  const std::string repaired = repair.describe();
  if (!repaired.empty()) text += (text.empty() ? "" : "; ") + repaired;
  return text.empty() ? text : path + ": " + text;
}

LoadedMesh readMesh(const std::string& path) {
  io::requireRegularFile<MeshError>(path, "a mesh file");
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw MeshError(path + ": cannot open mesh file (missing or unreadable)");
  }
  const RawMesh raw = hasExtension(path, ".ply")   ? plyToRaw(detail::readPly(path))
                     : hasExtension(path, ".vtp") ? vtpToRaw(readVtpPolyData(path))
                                                    : readAssimpRaw(path);
  return finishMesh(raw, path);
}

LoadedMesh parseMesh(const std::string& bytes, const std::string& path) {
  if (hasExtension(path, ".ply")) return finishMesh(plyToRaw(detail::parsePly(bytes, path)), path);
  if (hasExtension(path, ".vtp")) return finishMesh(vtpToRaw(parseVtpPolyData(bytes, path)), path);
  throw MeshError(path + ": only .ply and .vtp meshes can be read from memory (expected one of those extensions)");
}

namespace {

/// Checks the raw mesh's coordinates and extent, then welds and repairs it.
LoadedMesh finishMesh(const RawMesh& raw, const std::string& path) {
  if (raw.triangles.empty()) throw MeshError(path + ": mesh contains no triangles");
  Eigen::AlignedBox3d box;
  for (const auto& t : raw.triangles)
    for (int v : t) {
      const Point& p = raw.vertices[static_cast<std::size_t>(v)];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        std::ostringstream msg;
        msg << path << ": non-finite coordinate in vertex " << v << " (" << p[0] << ", " << p[1]
            << ", " << p[2] << ")";
        throw MeshError(msg.str());
      }
      if (std::abs(p[0]) > kMaxMeshCoordinate || std::abs(p[1]) > kMaxMeshCoordinate ||
          std::abs(p[2]) > kMaxMeshCoordinate) {
        std::ostringstream msg;
        msg << path << ": vertex " << v << " (" << p[0] << ", " << p[1] << ", " << p[2]
            << ") has a coordinate of magnitude above " << kMaxMeshCoordinate
            << " (wrong units or a corrupt file?)";
        throw MeshError(msg.str());
      }
      box.extend(Eigen::Vector3d(p[0], p[1], p[2]));
    }
  const double extent = box.sizes().maxCoeff();
  if (!(extent >= kMinMeshExtent)) {
    std::ostringstream msg;
    msg << path << ": the mesh spans only " << extent << " (largest side of its bounding box), less than "
        << kMinMeshExtent << " (wrong units or a collapsed mesh?)";
    throw MeshError(msg.str());
  }
  LoadedMesh loaded;
  loaded.mesh = weld(raw, loaded.unused_vertices);
  loaded.repair = repairMesh(loaded.mesh);
  if (loaded.mesh.countTriangles() == 0)  // every triangle was collapsed or a duplicate
    throw MeshError(path + ": mesh contains no triangles once collapsed and duplicate triangles are removed (" +
                    std::to_string(raw.triangles.size()) + " in the file)");
  return loaded;
}

}  // namespace

TriangleMesh loadMesh(const std::string& path, const MeshWarningFn& warn) {
  LoadedMesh loaded = readMesh(path);
  const std::string warning = loaded.describeDefects(path);
  if (!warning.empty() && warn) warn(warning);
  return std::move(loaded.mesh);
}

void writePly(const std::string& path, const TriangleMesh& mesh) {
  std::string data;
  {
    std::ostringstream header;
    header << "ply\nformat binary_little_endian 1.0\ncomment rbfmuscle, units mm\n"
           << "element vertex " << mesh.countVertices() << "\nproperty double x\n"
           << "property double y\nproperty double z\nelement face " << mesh.countTriangles()
           << "\nproperty list uchar int vertex_indices\nend_header\n";
    data = header.str();
  }
  data.reserve(data.size() + 24 * std::size_t(mesh.countVertices()) +
               13 * std::size_t(mesh.countTriangles()));
  for (int v = 0; v < mesh.countVertices(); ++v)
    for (int k = 0; k < 3; ++k) {
      std::uint64_t bits;
      const double x = mesh.vertices_mm(k, v);
      std::memcpy(&bits, &x, sizeof bits);
      appendLittleEndian(data, bits, 8);
    }
  for (int t = 0; t < mesh.countTriangles(); ++t) {
    data.push_back(3);
    for (int c = 0; c < 3; ++c)
      appendLittleEndian(data, static_cast<std::uint32_t>(mesh.triangles(c, t)), 4);
  }
  const std::string temp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(data.data(), static_cast<std::streamsize>(data.size()));
    out.close();
    if (!out) {
      std::remove(temp.c_str());
      throw MeshError(path + ": cannot write PLY file (temporary " + temp + " failed)");
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    std::remove(temp.c_str());
    throw MeshError(path + ": cannot write PLY file (rename from " + temp + " failed)");
  }
}

std::string hashFile(const std::string& path) {
  io::requireRegularFile<MeshError>(path, "a file to hash");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError(path + ": cannot open file to hash (missing or unreadable)");
  std::uint64_t hash = 0xcbf29ce484222325ull;
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const std::streamsize n = in.gcount();
    for (std::streamsize i = 0; i < n; ++i) {
      hash ^= static_cast<unsigned char>(buffer[static_cast<std::size_t>(i)]);
      hash *= 0x100000001b3ull;
    }
  }
  if (in.bad()) throw MeshError(path + ": read error while hashing");
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  return hex;
}

}  // namespace rbfmuscle
