// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_edges.h"

#include <algorithm>
#include <cstdint>

namespace rbfmuscle::detail {

EdgeTable buildEdgeTable(const TriangleMesh& mesh) {
  const int T = mesh.countTriangles();
  struct Side {
    std::int64_t key;  // lo · V + hi
    int slot;          // 3t + c
    bool forward;
  };
  const std::int64_t V = std::max(1, mesh.countVertices());
  std::vector<Side> sides;
  sides.reserve(3 * std::size_t(T));
  for (int t = 0; t < T; ++t)
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.triangles(c, t), b = mesh.triangles((c + 1) % 3, t);
      sides.push_back({std::int64_t(std::min(a, b)) * V + std::max(a, b), 3 * t + c, a <= b});
    }
  std::sort(sides.begin(), sides.end(),
            [](const Side& x, const Side& y) { return x.key < y.key || (x.key == y.key && x.slot < y.slot); });
  EdgeTable table;
  table.of_triangle.resize(3, T);
  for (std::size_t i = 0; i < sides.size(); ++i) {
    if (i == 0 || sides[i].key != sides[i - 1].key) {
      table.vertices.push_back({int(sides[i].key / V), int(sides[i].key % V)});
      table.use_count.push_back(0);
      table.forward_count.push_back(0);
    }
    const int e = int(table.vertices.size()) - 1;
    table.use_count[e] += 1;
    table.forward_count[e] += sides[i].forward ? 1 : 0;
    table.of_triangle(sides[i].slot % 3, sides[i].slot / 3) = e;
  }
  return table;
}

}  // namespace rbfmuscle::detail
