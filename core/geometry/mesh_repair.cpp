// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>
#include <vector>

#include "geometry/disjoint_sets.h"
#include "geometry/mesh_edges.h"
#include "geometry/mesh_measures.h"
#include "geometry/pinch_split.h"

namespace rbfmuscle {
namespace {

/// "1 vertex" / "3 vertices".
std::string count(int n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

/// "a", "a and b", "a, b and c".
std::string joinList(const std::vector<std::string>& items) {
  std::string s;
  for (std::size_t i = 0; i < items.size(); ++i)
    s += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
  return s;
}

/// The mesh with only the triangles marked in `keep`.
TriangleMesh keepTriangles(const TriangleMesh& mesh, const std::vector<char>& keep) {
  TriangleMesh out;
  out.vertices_mm = mesh.vertices_mm;
  out.triangles.resize(3, Eigen::Index(std::count(keep.begin(), keep.end(), 1)));
  Eigen::Index k = 0;
  for (int t = 0; t < mesh.countTriangles(); ++t)
    if (keep[std::size_t(t)]) out.triangles.col(k++) = mesh.triangles.col(t);
  return out;
}

/// Step 2: per set of three vertices, back-to-back pairs cancel and one of several triangles
/// wound the same way stays. Marks the removed triangles in `keep`.
void reduceSameVertexTriangles(const TriangleMesh& mesh, std::vector<char>& keep, MeshRepairReport& report) {
  const int T = mesh.countTriangles();
  std::vector<std::array<int, 3>> key(static_cast<std::size_t>(T));
  for (int t = 0; t < T; ++t) {
    key[std::size_t(t)] = {mesh.triangles(0, t), mesh.triangles(1, t), mesh.triangles(2, t)};
    std::sort(key[std::size_t(t)].begin(), key[std::size_t(t)].end());
  }
  std::vector<int> order(static_cast<std::size_t>(T));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return key[std::size_t(a)] < key[std::size_t(b)] || (key[std::size_t(a)] == key[std::size_t(b)] && a < b);
  });
  // Winding of t against its sorted vertices: true when it is an even permutation of them.
  const auto evenWinding = [&](int t) {
    int c = 0;
    while (mesh.triangles(c, t) != key[std::size_t(t)][0]) ++c;
    return mesh.triangles((c + 1) % 3, t) < mesh.triangles((c + 2) % 3, t);
  };
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i + 1;
    while (j < order.size() && key[std::size_t(order[j])] == key[std::size_t(order[i])]) ++j;
    if (j - i > 1) {
      std::vector<int> even, odd;
      for (std::size_t k = i; k < j; ++k) (evenWinding(order[k]) ? even : odd).push_back(order[k]);
      report.back_to_back_pairs += int(std::min(even.size(), odd.size()));
      const std::vector<int>& more = even.size() > odd.size() ? even : odd;
      const int excess = std::abs(int(even.size()) - int(odd.size()));
      report.duplicate_triangles += std::max(0, excess - 1);
      for (std::size_t k = i; k < j; ++k) keep[std::size_t(order[k])] = 0;
      if (excess > 0) keep[std::size_t(more.front())] = 1;
    }
    i = j;
  }
}

/// Step 4: marks in `keep` the triangles of closed shells that touch a split vertex and
/// enclose at most `fraction` of the mesh's volume; never the shell of largest |volume|.
void removeDetachedShells(const TriangleMesh& mesh, const std::vector<char>& at_pinch, double fraction,
                          std::vector<char>& keep, MeshRepairReport& report) {
  const int T = mesh.countTriangles();
  DisjointSets shells(std::size_t(mesh.countVertices()));
  for (int t = 0; t < T; ++t)
    for (int c = 1; c < 3; ++c) shells.join(mesh.triangles(c, t), mesh.triangles(0, t));
  // Each shell's volume about one of its own vertices (a closed shell's volume does not depend
  // on the point; a near one keeps the round-off at the shell's own scale).
  std::vector<double> six_volume(shells.size(), 0.0);
  std::vector<int> triangles(shells.size(), 0);
  std::vector<char> touches(shells.size(), 0);
  double total = 0.0;
  for (int t = 0; t < T; ++t) {
    const int root = shells.find(mesh.triangles(0, t));
    const Eigen::Vector3d o = mesh.vertices_mm.col(root);
    const double v = (mesh.getCorner(t, 0) - o).dot((mesh.getCorner(t, 1) - o).cross(mesh.getCorner(t, 2) - o));
    six_volume[std::size_t(root)] += v;
    total += v;
    triangles[std::size_t(root)] += 1;
    for (int c = 0; c < 3; ++c) touches[std::size_t(root)] |= at_pinch[std::size_t(mesh.triangles(c, t))];
  }
  int largest = -1;
  for (std::size_t r = 0; r < shells.size(); ++r)
    if (triangles[r] > 0 && (largest < 0 || std::abs(six_volume[r]) > std::abs(six_volume[std::size_t(largest)])))
      largest = int(r);
  std::vector<char> remove(shells.size(), 0);
  for (std::size_t r = 0; r < shells.size(); ++r) {
    if (triangles[r] == 0 || !touches[r] || int(r) == largest) continue;
    if (!(std::abs(six_volume[r]) <= fraction * std::abs(total))) continue;
    remove[r] = 1;
    report.removed_shells += 1;
    report.removed_shell_triangles += triangles[r];
    report.removed_shell_volume_mm3 += six_volume[r] / 6.0;
  }
  for (int t = 0; t < T; ++t)
    if (remove[std::size_t(shells.find(mesh.triangles(0, t)))]) keep[std::size_t(t)] = 0;
}

/// Where a removed shell took the original of a split vertex, the copy still in use goes back
/// to the original's index (copy i of `copy_of` is vertex `original_count` + i).
void reuseFreedOriginals(TriangleMesh& mesh, int original_count, const std::vector<int>& copy_of) {
  std::vector<char> used(std::size_t(mesh.countVertices()), 0);
  for (int t = 0; t < mesh.countTriangles(); ++t)
    for (int c = 0; c < 3; ++c) used[std::size_t(mesh.triangles(c, t))] = 1;
  std::vector<int> index(used.size());
  std::iota(index.begin(), index.end(), 0);
  for (std::size_t i = 0; i < copy_of.size(); ++i) {
    const std::size_t copy = std::size_t(original_count) + i, original = std::size_t(copy_of[i]);
    if (used[copy] && !used[original]) {
      index[copy] = int(original);
      used[original] = 1;
      used[copy] = 0;
    }
  }
  for (int t = 0; t < mesh.countTriangles(); ++t)
    for (int c = 0; c < 3; ++c) mesh.triangles(c, t) = index[std::size_t(mesh.triangles(c, t))];
}

/// Drops vertices no triangle uses, keeping the order of the others. Counts, in `report`,
/// the dropped vertices below `original_count` and the copies (at or above it) kept.
void dropUnusedVertices(TriangleMesh& mesh, int original_count, MeshRepairReport& report) {
  std::vector<int> index(std::size_t(mesh.countVertices()), -1);
  for (int t = 0; t < mesh.countTriangles(); ++t)
    for (int c = 0; c < 3; ++c) index[std::size_t(mesh.triangles(c, t))] = 0;
  int next = 0;
  for (std::size_t v = 0; v < index.size(); ++v) {
    if (index[v] < 0) {
      report.dropped_vertices += int(v) < original_count ? 1 : 0;
      continue;
    }
    report.vertex_copies += int(v) >= original_count ? 1 : 0;
    mesh.vertices_mm.col(next) = mesh.vertices_mm.col(Eigen::Index(v));
    index[v] = next++;
  }
  mesh.vertices_mm.conservativeResize(3, next);
  for (int t = 0; t < mesh.countTriangles(); ++t)
    for (int c = 0; c < 3; ++c) mesh.triangles(c, t) = index[std::size_t(mesh.triangles(c, t))];
}

}  // namespace

bool MeshRepairReport::changedMesh() const {
  return collapsed_triangles + back_to_back_pairs + duplicate_triangles + vertex_copies + removed_shells +
             dropped_vertices >
         0;
}

std::string MeshRepairReport::describe() const {
  if (!foundDefects()) return "";
  std::vector<std::string> found, removed, done;
  if (non_manifold_edges > 0) found.push_back(count(non_manifold_edges, "non-manifold edge", "non-manifold edges"));
  if (pinched_vertices > 0) found.push_back(count(pinched_vertices, "pinched vertex", "pinched vertices"));
  if (collapsed_triangles > 0)
    removed.push_back(count(collapsed_triangles, "collapsed triangle", "collapsed triangles") +
                      " (a repeated vertex)");
  if (back_to_back_pairs > 0)
    removed.push_back(count(back_to_back_pairs, "back-to-back triangle pair", "back-to-back triangle pairs"));
  if (duplicate_triangles > 0)
    removed.push_back(count(duplicate_triangles, "duplicate triangle", "duplicate triangles"));
  if (removed_shells > 0) {
    std::ostringstream s;
    s.precision(3);
    s << count(removed_shells, "detached shell", "detached shells") << " ("
      << count(removed_shell_triangles, "triangle", "triangles") << ", " << removed_shell_volume_mm3 << " mm³)";
    removed.push_back(s.str());
  }
  if (!removed.empty()) done.push_back("removed " + joinList(removed));
  if (vertex_copies > 0)
    done.push_back("added " + count(vertex_copies, "vertex copy", "vertex copies") + " (one per further sheet at a pinch)");
  if (dropped_vertices > 0) done.push_back("dropped " + count(dropped_vertices, "vertex", "vertices") + " left unused");
  std::ostringstream s;
  s.precision(10);
  if (changedMesh()) {
    s << (found.empty() || leftDefects() ? std::string("repaired") : joinList(found) + " repaired") << ": ";
    for (std::size_t i = 0; i < done.size(); ++i) s << (i ? "; " : "") << done[i];
    s << "; volume " << volume_before_mm3 << " mm³ before, " << volume_after_mm3 << " mm³ after";
  }
  if (cancels_out)
    s << (changedMesh() ? "; " : "") << "every triangle has a back-to-back twin, so the surface encloses nothing; "
      << "left as it is";
  else if (unsplit_edges > 0)
    s << (changedMesh() ? "; " : "") << "could not split "
      << count(unsplit_edges, "non-manifold edge", "non-manifold edges")
      << " (the mesh is open or inconsistently wound, or the triangles on the edge do not pair into sheets)";
  return s.str();
}

MeshRepairReport repairMesh(TriangleMesh& mesh, const MeshRepairOptions& options) {
  MeshRepairReport report;
  report.volume_before_mm3 = calcVolume(mesh);
  report.volume_after_mm3 = report.volume_before_mm3;
  const int T = mesh.countTriangles(), V = mesh.countVertices();

  // Step 1: collapsed triangles.
  std::vector<char> keep(std::size_t(T), 1);
  for (int t = 0; t < T; ++t) {
    const int a = mesh.triangles(0, t), b = mesh.triangles(1, t), c = mesh.triangles(2, t);
    if (a == b || b == c || c == a) {
      keep[std::size_t(t)] = 0;
      ++report.collapsed_triangles;
    }
  }
  TriangleMesh work = report.collapsed_triangles > 0 ? keepTriangles(mesh, keep) : mesh;
  {
    const detail::EdgeTable edges = detail::buildEdgeTable(work);
    report.non_manifold_edges = int(std::count_if(edges.use_count.begin(), edges.use_count.end(),
                                                  [](int uses) { return uses > 2; }));
  }

  // Step 2: triangles on the same three vertices.
  keep.assign(std::size_t(work.countTriangles()), 1);
  reduceSameVertexTriangles(work, keep, report);
  if (work.countTriangles() > 0 && std::find(keep.begin(), keep.end(), 1) == keep.end()) {
    report.cancels_out = true;
    report.back_to_back_pairs = report.duplicate_triangles = 0;
    report.unsplit_edges = report.non_manifold_edges;
    if (report.collapsed_triangles > 0) {
      dropUnusedVertices(work, V, report);
      report.volume_after_mm3 = calcVolume(work);
      mesh = std::move(work);
    }
    return report;
  }
  if (report.back_to_back_pairs + report.duplicate_triangles > 0) work = keepTriangles(work, keep);

  // Step 3: pinches.
  const detail::PinchSplit split = detail::splitPinches(work);
  report.pinched_vertices = split.pinched_vertices;
  report.unsplit_edges = split.unsplit_edges;

  // Step 4: shells the split detached.
  if (split.vertex_copies > 0) {
    keep.assign(std::size_t(work.countTriangles()), 1);
    removeDetachedShells(work, split.at_pinch, options.max_detached_shell_volume_fraction, keep, report);
    if (report.removed_shells > 0) {
      work = keepTriangles(work, keep);
      reuseFreedOriginals(work, V, split.copy_of);
    }
  }

  if (report.collapsed_triangles + report.back_to_back_pairs + report.duplicate_triangles +
          split.vertex_copies >
      0) {
    dropUnusedVertices(work, V, report);
    report.volume_after_mm3 = calcVolume(work);
    mesh = std::move(work);
  }
  return report;
}

}  // namespace rbfmuscle
