// SPDX-License-Identifier: Apache-2.0
#include "geometry/move_out_of_solids.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace rbfmuscle {
namespace {

/// Where each vertex deeper than the tolerance must go: onto the nearest face of the solid it
/// lies deepest in (mesh frame, mm). Vertices not inside keep a NaN target.
struct FaceTargets {
  Eigen::Matrix3Xd move_mm;       ///< per vertex: its move onto the face, NaN when not inside
  std::vector<int> inside;        ///< the vertices inside
  double depth_max_mm = 0;
  std::string deepest_solid;
};

FaceTargets findFaceTargets(const TriangleMesh& mesh, const std::vector<PlacedSolid>& solids, double tolerance_mm,
                            double clearance_mm) {
  FaceTargets targets;
  const int n = mesh.countVertices();
  targets.move_mm.setConstant(3, n, std::nan(""));
  std::vector<double> depth(static_cast<size_t>(n), tolerance_mm);
  for (const PlacedSolid& solid : solids) {
    const Eigen::AlignedBox3d box_S = solid.distance->getMesh().calcBoundingBox();
    const Eigen::Isometry3d X_solid_mesh = solid.X_mesh_solid.inverse();
    for (int v = 0; v < n; ++v) {
      const Eigen::Vector3d p_S = X_solid_mesh * mesh.vertices_mm.col(v);
      if (!box_S.contains(p_S)) continue;  // outside its box, so outside the solid
      const SignedClosestPoint closest = solid.distance->findSignedClosestPoint(p_S);
      if (-closest.signed_distance_mm <= depth[static_cast<size_t>(v)]) continue;
      depth[static_cast<size_t>(v)] = -closest.signed_distance_mm;
      const Eigen::Vector3d to_face = solid.X_mesh_solid * closest.point_mm - mesh.vertices_mm.col(v);
      targets.move_mm.col(v) = to_face * (1.0 + clearance_mm / to_face.norm());
      if (depth[static_cast<size_t>(v)] > targets.depth_max_mm) {
        targets.depth_max_mm = depth[static_cast<size_t>(v)];
        targets.deepest_solid = solid.name;
      }
    }
  }
  for (int v = 0; v < n; ++v)
    if (!std::isnan(targets.move_mm(0, v))) targets.inside.push_back(v);
  return targets;
}

/// The harmonic extension of the face moves: fixed at the inside vertices, zero at vertices
/// farther than `fade_mm` from all of them and at those no path of free vertices joins to a
/// fixed one; the uniform Laplacian over the mesh's edges vanishes at the rest.
Eigen::Matrix3Xd extendMoves(const TriangleMesh& mesh, const FaceTargets& targets, double fade_mm) {
  const int n = mesh.countVertices();
  Eigen::Matrix3Xd move = Eigen::Matrix3Xd::Zero(3, n);
  std::vector<char> fixed(static_cast<size_t>(n), 1);
  for (int v = 0; v < n; ++v) {
    if (!std::isnan(targets.move_mm(0, v))) {
      move.col(v) = targets.move_mm.col(v);
      continue;
    }
    for (int u : targets.inside)
      if ((mesh.vertices_mm.col(v) - mesh.vertices_mm.col(u)).squaredNorm() < fade_mm * fade_mm) {
        fixed[static_cast<size_t>(v)] = 0;
        break;
      }
  }
  std::vector<std::vector<int>> neighbours(static_cast<size_t>(n));
  for (int t = 0; t < mesh.countTriangles(); ++t)
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.triangles(c, t), b = mesh.triangles((c + 1) % 3, t);
      neighbours[static_cast<size_t>(a)].push_back(b);
      neighbours[static_cast<size_t>(b)].push_back(a);
    }
  // Free vertices that no path of free vertices joins to an inside vertex stay where they are
  // (without this, a free piece of the mesh would leave the system singular).
  std::vector<char> reached(static_cast<size_t>(n), 0);
  std::vector<int> stack(targets.inside);
  for (int v : stack) reached[static_cast<size_t>(v)] = 1;
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    for (int u : neighbours[static_cast<size_t>(v)])
      if (!fixed[static_cast<size_t>(u)] && !reached[static_cast<size_t>(u)]) {
        reached[static_cast<size_t>(u)] = 1;
        stack.push_back(u);
      }
  }
  std::vector<int> index(static_cast<size_t>(n), -1);
  std::vector<int> free;
  for (int v = 0; v < n; ++v)
    if (!fixed[static_cast<size_t>(v)] && reached[static_cast<size_t>(v)]) {
      index[static_cast<size_t>(v)] = static_cast<int>(free.size());
      free.push_back(v);
    }
  if (free.empty()) return move;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(free.size()), 3);
  for (size_t i = 0; i < free.size(); ++i) {
    const int v = free[i];
    for (int u : neighbours[static_cast<size_t>(v)]) {
      entries.emplace_back(static_cast<int>(i), static_cast<int>(i), 1.0);
      if (index[static_cast<size_t>(u)] >= 0)
        entries.emplace_back(static_cast<int>(i), index[static_cast<size_t>(u)], -1.0);
      else
        rhs.row(static_cast<Eigen::Index>(i)) += move.col(u).transpose();
    }
  }
  Eigen::SparseMatrix<double> laplacian(static_cast<Eigen::Index>(free.size()), static_cast<Eigen::Index>(free.size()));
  laplacian.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
  if (solver.info() != Eigen::Success) throw std::runtime_error("moveOutOfSolids: the Laplacian did not factor");
  const Eigen::MatrixX3d solved = solver.solve(rhs);
  for (size_t i = 0; i < free.size(); ++i) move.col(free[i]) = solved.row(static_cast<Eigen::Index>(i)).transpose();
  return move;
}

}  // namespace

MoveOutReport moveOutOfSolids(TriangleMesh& mesh, const std::vector<PlacedSolid>& solids,
                              const MoveOutSettings& settings) {
  for (const PlacedSolid& solid : solids)
    if (solid.distance == nullptr) throw std::invalid_argument("moveOutOfSolids: solid '" + solid.name + "' is null");
  if (!(settings.tolerance_mm >= 0) || !(settings.clearance_mm >= 0) || !(settings.fade_mm > 0) || settings.max_rounds < 1)
    throw std::invalid_argument(
        "moveOutOfSolids: expected tolerance_mm >= 0, clearance_mm >= 0, fade_mm > 0 and max_rounds >= 1");
  MoveOutReport report;
  const Eigen::Matrix3Xd start_mm = mesh.vertices_mm;
  report.stop = "round cap";
  for (report.rounds = 0; report.rounds <= settings.max_rounds; ++report.rounds) {
    const FaceTargets targets = findFaceTargets(mesh, solids, settings.tolerance_mm, settings.clearance_mm);
    if (report.rounds == 0) {
      report.vertices_inside = static_cast<int>(targets.inside.size());
      report.depth_max_mm = targets.depth_max_mm;
      report.deepest_solid = targets.deepest_solid;
    }
    report.vertices_left = static_cast<int>(targets.inside.size());
    if (targets.inside.empty()) {
      report.stop = "none inside";
      break;
    }
    if (report.rounds == settings.max_rounds) break;
    mesh.vertices_mm += extendMoves(mesh, targets, settings.fade_mm);
  }
  const Eigen::VectorXd moved = (mesh.vertices_mm - start_mm).colwise().norm();
  report.vertices_moved = static_cast<int>((moved.array() > 1e-3).count());
  report.move_max_mm = moved.size() ? moved.maxCoeff() : 0.0;
  return report;
}

std::string describeMoveOut(const std::string& mesh_path, const MoveOutReport& report,
                            const MoveOutSettings& settings) {
  if (report.vertices_inside == 0) return "";
  std::ostringstream text;
  text.precision(3);
  text << mesh_path << ": " << report.vertices_inside << " vertices lay more than " << settings.tolerance_mm
       << " mm inside the solids it must not enter (the deepest " << report.depth_max_mm << " mm, in "
       << report.deepest_solid << "): moved to " << settings.clearance_mm
       << " mm outside their faces, with the mesh within " << settings.fade_mm << " mm of them ("
       << report.vertices_moved << " vertices moved, up to " << report.move_max_mm << " mm; "
       << (report.stop == "none inside" ? "none left inside" : std::to_string(report.vertices_left) + " left inside at the round cap")
       << " after " << report.rounds << (report.rounds == 1 ? " round)" : " rounds)");
  return text.str();
}

}  // namespace rbfmuscle
