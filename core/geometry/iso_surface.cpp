// SPDX-License-Identifier: Apache-2.0
#include "geometry/iso_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace rbfmuscle {
namespace {

constexpr double kSnap = 1e-3;  // vertices stay this fraction of an edge away from nodes

/// The 6 Kuhn tetrahedra of the unit cube: corners 0 → e_a → e_a + e_b → (1,1,1) for each
/// axis order (a, b, c). Corner offsets are bit masks (x = 1, y = 2, z = 4); along each
/// tetrahedron the masks grow, so every edge runs from a lower to a higher node.
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                             {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

class Extractor {
 public:
  Extractor(const ScalarFieldFn& field, const Eigen::AlignedBox3d& box, double cell)
      : field_(field), origin_(box.min()), cell_(cell), n_(countIsoSurfaceNodes(box, cell)) {}

  TriangleMesh run() {
    std::vector<double> below = evaluateLayer(0), above;
    for (std::int64_t k = 0; k + 1 < n_[2]; ++k) {
      above = evaluateLayer(k + 1);
      for (std::int64_t j = 0; j + 1 < n_[1]; ++j)
        for (std::int64_t i = 0; i + 1 < n_[0]; ++i) processCube(i, j, k, below, above);
      below.swap(above);
    }
    TriangleMesh mesh;
    mesh.vertices_mm.resize(3, Eigen::Index(vertices_.size()));
    for (std::size_t v = 0; v < vertices_.size(); ++v) mesh.vertices_mm.col(Eigen::Index(v)) = vertices_[v];
    mesh.triangles.resize(3, Eigen::Index(triangles_.size()));
    for (std::size_t t = 0; t < triangles_.size(); ++t)
      for (int c = 0; c < 3; ++c) mesh.triangles(c, Eigen::Index(t)) = triangles_[t][std::size_t(c)];
    return mesh;
  }

  std::int64_t getClippedNodes() const { return clipped_nodes_; }
  std::vector<std::uint64_t>& updVertexEdges() { return vertex_edges_; }

 private:
  Eigen::Vector3d nodePosition(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return origin_ + cell_ * Eigen::Vector3d(double(i), double(j), double(k));
  }

  std::vector<double> evaluateLayer(std::int64_t k) {
    Eigen::Matrix3Xd points(3, n_[0] * n_[1]);
    for (std::int64_t j = 0; j < n_[1]; ++j)
      for (std::int64_t i = 0; i < n_[0]; ++i) points.col(i + n_[0] * j) = nodePosition(i, j, k);
    Eigen::VectorXd values;
    field_(points, values);
    if (values.size() != points.cols()) {
      std::ostringstream s;
      s << "extractIsoSurface: field returned " << values.size() << " values for "
        << points.cols() << " points";
      throw std::runtime_error(s.str());
    }
    for (Eigen::Index p = 0; p < values.size(); ++p)
      if (!std::isfinite(values[p])) {
        std::ostringstream s;
        s << "extractIsoSurface: field value " << values[p] << " at ("
          << points.col(p).transpose() << ") mm is not finite";
        throw std::runtime_error(s.str());
      }
    // Close the surface at the box: a node on a box face counts as outside.
    for (std::int64_t j = 0; j < n_[1]; ++j)
      for (std::int64_t i = 0; i < n_[0]; ++i) {
        const bool on_face = k == 0 || k == n_[2] - 1 || j == 0 || j == n_[1] - 1 || i == 0 || i == n_[0] - 1;
        double& value = values[i + n_[0] * j];
        if (on_face && value > 0.0) {
          value = 0.0;
          ++clipped_nodes_;
        }
      }
    return std::vector<double>(values.data(), values.data() + values.size());
  }

  void processCube(std::int64_t i, std::int64_t j, std::int64_t k, const std::vector<double>& below,
                   const std::vector<double>& above) {
    std::array<double, 8> f;
    std::array<std::int64_t, 8> id;
    std::array<Eigen::Vector3d, 8> x;
    int inside_count = 0;
    for (int m = 0; m < 8; ++m) {
      const std::int64_t ii = i + (m & 1), jj = j + ((m >> 1) & 1);
      f[std::size_t(m)] = ((m & 4) ? above : below)[std::size_t(ii + n_[0] * jj)];
      inside_count += f[std::size_t(m)] > 0.0 ? 1 : 0;
    }
    if (inside_count == 0 || inside_count == 8) return;  // most cubes: nothing more to do
    for (int m = 0; m < 8; ++m) {
      const std::int64_t ii = i + (m & 1), jj = j + ((m >> 1) & 1), kk = k + ((m >> 2) & 1);
      id[std::size_t(m)] = ii + n_[0] * (jj + n_[1] * kk);
      x[std::size_t(m)] = nodePosition(ii, jj, kk);
    }
    for (const auto& tet : kTets) processTet(tet, f, id, x);
  }

  /// Vertex on the edge between cube corners lo < hi (bit masks), created once per edge.
  int edgeVertex(int lo, int hi, const std::array<double, 8>& f,
                 const std::array<std::int64_t, 8>& id, const std::array<Eigen::Vector3d, 8>& x) {
    const std::uint64_t key = std::uint64_t(id[std::size_t(lo)]) * 8u + std::uint64_t(hi - lo);
    const auto found = edge_vertex_.find(key);
    if (found != edge_vertex_.end()) return found->second;
    const double f0 = f[std::size_t(lo)], f1 = f[std::size_t(hi)];
    const double t = std::clamp(f0 / (f0 - f1), kSnap, 1.0 - kSnap);
    vertices_.push_back(x[std::size_t(lo)] + t * (x[std::size_t(hi)] - x[std::size_t(lo)]));
    vertex_edges_.push_back(key);
    const int v = int(vertices_.size()) - 1;
    edge_vertex_.emplace(key, v);
    return v;
  }

  /// Adds triangle (a, b, c), reversed if its normal does not point along `outward`.
  void addTriangle(int a, int b, int c, const Eigen::Vector3d& outward) {
    const Eigen::Vector3d n = (vertices_[std::size_t(b)] - vertices_[std::size_t(a)])
                                  .cross(vertices_[std::size_t(c)] - vertices_[std::size_t(a)]);
    if (n.dot(outward) >= 0.0) triangles_.push_back({a, b, c});
    else triangles_.push_back({a, c, b});
  }

  void processTet(const int (&tet)[4], const std::array<double, 8>& f,
                  const std::array<std::int64_t, 8>& id, const std::array<Eigen::Vector3d, 8>& x) {
    std::array<int, 4> in{}, out{};
    int n_in = 0, n_out = 0;
    for (int c : tet) (f[std::size_t(c)] > 0.0 ? in[std::size_t(n_in++)] : out[std::size_t(n_out++)]) = c;
    if (n_in == 0 || n_out == 0) return;
    const auto vertexOn = [&](int a, int b) {
      return a < b ? edgeVertex(a, b, f, id, x) : edgeVertex(b, a, f, id, x);
    };
    Eigen::Vector3d in_centre = Eigen::Vector3d::Zero(), out_centre = Eigen::Vector3d::Zero();
    for (int c = 0; c < n_in; ++c) in_centre += x[std::size_t(in[std::size_t(c)])] / n_in;
    for (int c = 0; c < n_out; ++c) out_centre += x[std::size_t(out[std::size_t(c)])] / n_out;
    const Eigen::Vector3d outward = out_centre - in_centre;
    if (n_in == 1 || n_out == 1) {
      // One corner cut off: a triangle on its three edges.
      const int apex = n_in == 1 ? in[0] : out[0];
      const auto& others = n_in == 1 ? out : in;
      addTriangle(vertexOn(apex, others[0]), vertexOn(apex, others[1]), vertexOn(apex, others[2]),
                  outward);
      return;
    }
    // Two and two: the quad (in0,out0) (in0,out1) (in1,out1) (in1,out0), cyclic on the faces.
    const int q0 = vertexOn(in[0], out[0]), q1 = vertexOn(in[0], out[1]),
              q2 = vertexOn(in[1], out[1]), q3 = vertexOn(in[1], out[0]);
    addTriangle(q0, q1, q2, outward);
    addTriangle(q0, q2, q3, outward);
  }

  const ScalarFieldFn& field_;
  std::int64_t clipped_nodes_ = 0;
  Eigen::Vector3d origin_;
  double cell_;
  std::array<std::int64_t, 3> n_;
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::uint64_t> vertex_edges_;  ///< per vertex: id(low node)·8 + (hi − lo corner mask)
  std::vector<std::array<int, 3>> triangles_;
  std::unordered_map<std::uint64_t, int> edge_vertex_;
};

}  // namespace

std::array<std::int64_t, 3> countIsoSurfaceNodes(const Eigen::AlignedBox3d& box_mm, double cell_mm) {
  std::array<std::int64_t, 3> n{};
  for (int k = 0; k < 3; ++k)
    n[static_cast<size_t>(k)] = std::max<std::int64_t>(2, std::int64_t(std::ceil(box_mm.sizes()[k] / cell_mm - 1e-9)) + 1);
  return n;
}

void checkIsoSurfaceGrid(const Eigen::AlignedBox3d& box_mm, double cell_mm) {
  constexpr double kMaxNodes = 1e9;
  const std::array<std::int64_t, 3> n = countIsoSurfaceNodes(box_mm, cell_mm);
  if (double(n[0]) * double(n[1]) * double(n[2]) > kMaxNodes) {
    std::ostringstream s;
    s << "a surface cell of " << cell_mm << " mm takes a grid of " << n[0] << "×" << n[1] << "×" << n[2]
      << " nodes, more than " << kMaxNodes << "; use a larger cell";
    throw std::invalid_argument(s.str());
  }
}

TriangleMesh extractIsoSurface(const ScalarFieldFn& field, const Eigen::AlignedBox3d& box_mm,
                               double cell_mm, std::int64_t* clipped_nodes, std::vector<std::uint64_t>* vertex_edges) {
  if (box_mm.isEmpty() || !box_mm.min().allFinite() || !box_mm.max().allFinite()) {
    std::ostringstream s;
    s << "extractIsoSurface: box [" << box_mm.min().transpose() << "] – ["
      << box_mm.max().transpose() << "] mm is empty or not finite";
    throw std::invalid_argument(s.str());
  }
  if (!(cell_mm > 0.0) || !std::isfinite(cell_mm))
    throw std::invalid_argument("extractIsoSurface: cell size " + std::to_string(cell_mm) +
                                " mm must be positive and finite");
  checkIsoSurfaceGrid(box_mm, cell_mm);
  Extractor extractor(field, box_mm, cell_mm);
  TriangleMesh mesh = extractor.run();
  if (clipped_nodes) *clipped_nodes = extractor.getClippedNodes();
  if (vertex_edges) vertex_edges->swap(extractor.updVertexEdges());
  return mesh;
}

}  // namespace rbfmuscle
