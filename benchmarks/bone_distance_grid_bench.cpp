// SPDX-License-Identifier: Apache-2.0
/// @file
/// BoneDistanceGrid: accuracy against MeshDistance, cost of filling bricks, cost of a warm
/// query (and of the exact query it replaces), on a sphere, a box and the femur.
///
///   bone_distance_grid_bench [--benchmark_filter=...] [google benchmark options]
///
/// Shapes (argument 0): 0 icosphere r = 20 mm (5120 triangles), 1 cube of 40 mm turned
/// about a skew axis, 2 models/hip/meshes/femur_r.ply. Near points: uniform on the surface,
/// moved along the triangle normal by U(−3, 3) mm (tests/unit/collision/grid_error.h).
/// Counters:
///   BM_Accuracy/shape/h_um         err_mean_mm, err_p99_mm, err_max_mm (|value − s| at 100000
///                                  near points), err_max_surface_mm (where |s| ≤ 0.5 mm),
///                                  not_near (points answered far)
///   BM_FillNearPoints/shape        per fresh grid answering 2000 near points (each query the
///                                  first in its brick or not): bricks_near, bricks_far,
///                                  queries_per_near_brick (MeshDistance searches, all
///                                  bricks, per near brick), ms_per_near_brick
///   BM_FillWholeGrid/shape/cells   every brick of the grid box built: bricks_near,
///                                  bricks_far, slots, node_MiB, fill_ms
///   BM_BuildAllBricks/shape        buildAllBricks() on a fresh grid (OpenMP threads; wall time)
///   BM_SampleWarm/shape            sample() on 1000 near points, bricks already built
///   BM_ExactQuery/shape            MeshDistance::findSignedClosestPoint on the same points
#include "collision/bone_distance_grid.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>
#include <string>

#include "geometry/mesh_distance.h"
#include "geometry/mesh_io.h"
#include "unit/collision/grid_error.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

/// The MeshDistance of shape `shape` (see the file comment), built once.
std::shared_ptr<const MeshDistance> shapeDistance(int shape) {
  static const std::shared_ptr<const MeshDistance> distances[3] = {
      std::make_shared<const MeshDistance>(test::makeIcosphere(20.0, 4)),
      [] {
        TriangleMesh cube = test::makeCube(40.0, -20.0);
        cube.vertices_mm = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() * cube.vertices_mm;
        return std::make_shared<const MeshDistance>(std::move(cube));
      }(),
      std::make_shared<const MeshDistance>(loadMesh(test::modelPath("hip/meshes/femur_r.ply")))};
  return distances[shape];
}

Eigen::Matrix3Xd nearPoints(int shape, int n, unsigned seed) {
  return test::sampleNearSurface(shapeDistance(shape)->getMesh(), n, 3.0, seed);
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void BM_Accuracy(benchmark::State& state) {
  BoneDistanceGridSettings settings;
  settings.spacing_mm = double(state.range(1)) / 1000.0;
  const Eigen::Matrix3Xd points = nearPoints(int(state.range(0)), 100000, 21);
  test::GridError e;
  for (auto _ : state) {
    const BoneDistanceGrid grid(shapeDistance(int(state.range(0))), settings);
    e = test::measureGridError(grid, points);
  }
  state.counters["err_mean_mm"] = e.mean_mm;
  state.counters["err_p99_mm"] = e.p99_mm;
  state.counters["err_max_mm"] = e.max_mm;
  state.counters["err_max_surface_mm"] = e.max_at_surface_mm;
  state.counters["not_near"] = e.not_near;
}
BENCHMARK(BM_Accuracy)
    ->ArgsProduct({{0, 1, 2}, {500, 1000, 2000}})
    ->ArgNames({"shape", "h_um"})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

void BM_FillNearPoints(benchmark::State& state) {
  const int shape = int(state.range(0));
  const Eigen::Matrix3Xd points = nearPoints(shape, 2000, 22);
  BoneDistanceGridStats stats;
  double ms = 0;
  for (auto _ : state) {
    const BoneDistanceGrid grid(shapeDistance(shape));
    const auto start = std::chrono::steady_clock::now();
    for (Eigen::Index i = 0; i < points.cols(); ++i) benchmark::DoNotOptimize(grid.sample(points.col(i)));
    ms = msSince(start);
    stats = grid.getStats();
  }
  state.counters["bricks_near"] = double(stats.bricks_near);
  state.counters["bricks_far"] = double(stats.bricks_far);
  state.counters["queries_per_near_brick"] = double(stats.distance_queries) / double(std::max<long long>(stats.bricks_near, 1));
  state.counters["ms_per_near_brick"] = ms / double(std::max<long long>(stats.bricks_near, 1));
}
BENCHMARK(BM_FillNearPoints)->Arg(0)->Arg(1)->Arg(2)->ArgName("shape")->Iterations(2)->Unit(benchmark::kMillisecond);

void BM_FillWholeGrid(benchmark::State& state) {
  const int shape = int(state.range(0));
  BoneDistanceGridSettings settings;
  settings.brick_cells = int(state.range(1));
  BoneDistanceGridStats stats;
  double ms = 0;
  for (auto _ : state) {
    const BoneDistanceGrid grid(shapeDistance(shape), settings);
    const Eigen::AlignedBox3d box = grid.getGridBox();
    const double brick_mm = settings.spacing_mm * settings.brick_cells;
    const auto start = std::chrono::steady_clock::now();
    for (double z = box.min().z() + brick_mm / 2; z < box.max().z(); z += brick_mm)
      for (double y = box.min().y() + brick_mm / 2; y < box.max().y(); y += brick_mm)
        for (double x = box.min().x() + brick_mm / 2; x < box.max().x(); x += brick_mm)
          benchmark::DoNotOptimize(grid.sample(Eigen::Vector3d(x, y, z)));
    ms = msSince(start);
    stats = grid.getStats();
  }
  const double nodes_per_brick = std::pow(settings.brick_cells + 1, 3);
  state.counters["slots"] = double(stats.brick_slots);
  state.counters["bricks_near"] = double(stats.bricks_near);
  state.counters["bricks_far"] = double(stats.bricks_far);
  state.counters["node_MiB"] = double(stats.bricks_near) * nodes_per_brick * sizeof(double) / (1024.0 * 1024.0);
  state.counters["fill_ms"] = ms;
}
BENCHMARK(BM_FillWholeGrid)
    ->ArgsProduct({{0, 2}, {4, 8, 16}})
    ->ArgNames({"shape", "cells"})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

void BM_BuildAllBricks(benchmark::State& state) {
  const int shape = int(state.range(0));
  BoneDistanceGridStats stats;
  for (auto _ : state) {
    const BoneDistanceGrid grid(shapeDistance(shape));
    grid.buildAllBricks();
    stats = grid.getStats();
  }
  state.counters["bricks_near"] = double(stats.bricks_near);
  state.counters["node_MiB"] = double(stats.nodes_stored) * sizeof(double) / (1024.0 * 1024.0);
}
BENCHMARK(BM_BuildAllBricks)->Arg(0)->Arg(2)->ArgName("shape")->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_SampleWarm(benchmark::State& state) {
  const int shape = int(state.range(0));
  const Eigen::Matrix3Xd points = nearPoints(shape, 1000, 23);
  const BoneDistanceGrid grid(shapeDistance(shape));
  for (Eigen::Index i = 0; i < points.cols(); ++i) grid.sample(points.col(i));
  for (auto _ : state)
    for (Eigen::Index i = 0; i < points.cols(); ++i) benchmark::DoNotOptimize(grid.sample(points.col(i)));
  state.SetItemsProcessed(state.iterations() * points.cols());
}
BENCHMARK(BM_SampleWarm)->Arg(0)->Arg(1)->Arg(2)->ArgName("shape")->Unit(benchmark::kMicrosecond);

void BM_ExactQuery(benchmark::State& state) {
  const int shape = int(state.range(0));
  const Eigen::Matrix3Xd points = nearPoints(shape, 1000, 23);
  const MeshDistance& distance = *shapeDistance(shape);
  for (auto _ : state)
    for (Eigen::Index i = 0; i < points.cols(); ++i) benchmark::DoNotOptimize(distance.findSignedClosestPoint(points.col(i)));
  state.SetItemsProcessed(state.iterations() * points.cols());
}
BENCHMARK(BM_ExactQuery)->Arg(0)->Arg(1)->Arg(2)->ArgName("shape")->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rbfmuscle

BENCHMARK_MAIN();
