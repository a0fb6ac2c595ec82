/// @file
/// MuscleDeformer benchmarks on a fitted muscle surface, with the errors that need the
/// core API: a muscle whose two attachment bones move by the same rigid motion T must
/// move rigidly (rigid-motion error), and a muscle taken to a pose and back must come
/// back to rest (restore error).
///
///   rbfmuscle_bench [--benchmark_format=json] [google benchmark options]
/// Environment: RBFMUSCLE_BENCH_RBF = .rbf file (default models/hip/surfaces/gluteus_maximus_r.rbf).
///
/// Attachments (generic, so any .rbf works): bone 0 holds the centres within 25 mm of the
/// highest centre (largest z in M), bone 1 those within 25 mm of the lowest one.
/// Counters (per benchmark run, from the last frame):
///   rigid_centre_error_mm  max_k |ξ_k − T ξ_k⁰| after update(T, T)  (mm)
///   rigid_volume_error     |V/V_rest − 1| after update(T, T)
///   restore_centre_error_mm max_k |ξ_k − ξ_k⁰| after update(I, R) then update(I, I) (mm)
///   restore_volume_error   |V/V_rest − 1| after coming back
///   iterations             descent iterations of the timed frame
///   predict_ms, descent_ms, volume_ms, topology_ms  the deformer's own stage times of that frame
#include "dynamics/attachment.h"
#include "dynamics/muscle_deformer.h"
#include "fit/rbf_file.h"

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace rbfmuscle {
namespace {

/// The surface of the benchmarks, read once.
const RbfSurface& benchSurface() {
  static const RbfSurface surface = [] {
    const char* env = std::getenv("RBFMUSCLE_BENCH_RBF");
    return readRbfFile(env ? std::string(env)
                           : std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip/surfaces/gluteus_maximus_r.rbf");
  }();
  return surface;
}

/// Bone 0: centres within 25 mm of the highest centre; bone 1: of the lowest one.
Attachments endAttachments(const GaussianField& field) {
  const Eigen::Matrix3Xd& c = field.getCentres();
  Eigen::Index top = 0, bottom = 0;
  c.row(2).maxCoeff(&top);
  c.row(2).minCoeff(&bottom);
  Attachments attachments = makeFreeAttachments(field.getNumCentres(), 2);
  attachByLandmarks(field, {{0, c.col(top), 25.0}, {1, c.col(bottom), 25.0}}, attachments);
  return attachments;
}

std::unique_ptr<MuscleDeformer> makeDeformer(int quadrature_points) {
  const GaussianField& field = benchSurface().field;
  DeformerSettings settings;
  settings.quadrature.target_count = quadrature_points;
  return std::make_unique<MuscleDeformer>(field, endAttachments(field), settings);
}

/// Largest distance between the columns of two 3×N matrices (mm).
double maxColumnDistance(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).colwise().norm().maxCoeff();
}

/// A rigid motion of both bones: 20° about a tilted axis through the origin of M, then 15 mm.
const Eigen::Isometry3d& rigidMotion() {
  static const Eigen::Isometry3d T = [] {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.rotate(Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d(1, 2, 3).normalized()));
    t.pretranslate(Eigen::Vector3d(10.0, -5.0, 10.0));
    return t;
  }();
  return T;
}

/// The deformer's stage times of the last measured frame as counters (ms).
void setStageCounters(benchmark::State& state, const DeformResult& r) {
  state.counters["predict_ms"] = r.predict_ms;
  state.counters["descent_ms"] = r.descent_ms;
  state.counters["volume_ms"] = r.volume_ms;
  state.counters["topology_ms"] = r.topology_ms;
}

/// Times the second of two updates (`first` untimed, then `second`) and reports, from
/// the last run, the largest centre distance to `expected_centres` as `<prefix>_centre_error_mm`,
/// |V/V_rest − 1| as `<prefix>_volume_error`, the descent iterations and the stage times.
void timeSecondFrame(benchmark::State& state, MuscleDeformer& deformer, const std::vector<Eigen::Isometry3d>& first,
                     const std::vector<Eigen::Isometry3d>& second, const Eigen::Matrix3Xd& expected_centres,
                     const std::string& prefix) {
  double centre_error = 0, volume_error = 0;
  DeformResult stages;
  for (auto _ : state) {
    state.PauseTiming();
    deformer.update(first);
    state.ResumeTiming();
    const DeformResult& r = deformer.update(second);
    state.PauseTiming();
    centre_error = maxColumnDistance(deformer.getField().getCentres(), expected_centres);
    volume_error = std::abs(r.volume_ratio - 1.0);
    stages = r;
    state.ResumeTiming();
  }
  setStageCounters(state, stages);
  state.counters[prefix + "_centre_error_mm"] = centre_error;
  state.counters[prefix + "_volume_error"] = volume_error;
  state.counters["iterations"] = stages.iterations;
  state.counters["centres"] = deformer.getRestField().getNumCentres();
}

void BM_RigidMotionFrame(benchmark::State& state) {
  auto deformer = makeDeformer(static_cast<int>(state.range(0)));
  const Eigen::Isometry3d& T = rigidMotion();
  const std::vector<Eigen::Isometry3d> moved{T, T}, still{Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()};
  timeSecondFrame(state, *deformer, still, moved, T * deformer->getRestField().getCentres(), "rigid");
}

void BM_RestoreFrame(benchmark::State& state) {
  auto deformer = makeDeformer(static_cast<int>(state.range(0)));
  const Eigen::Matrix3Xd& rest = deformer->getRestField().getCentres();
  // Bone 1 swings 30° about an axis through the centroid of bone 0's centres.
  const Attachments& a = deformer->getAttachments();
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
  for (int k = 0; k < rest.cols(); ++k)
    if (a.bone_of_centre[static_cast<size_t>(k)] == 0) pivot += rest.col(k);
  pivot /= std::max(1, a.countAttachedTo(0));
  Eigen::Isometry3d R = Eigen::Isometry3d::Identity();
  R.translate(pivot).rotate(Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitX())).translate(-pivot);
  const std::vector<Eigen::Isometry3d> swung{Eigen::Isometry3d::Identity(), R},
      still{Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()};
  timeSecondFrame(state, *deformer, swung, still, rest, "restore");
}

BENCHMARK(BM_RigidMotionFrame)->Arg(1000)->Arg(4000)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RestoreFrame)->Arg(1000)->Arg(4000)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace rbfmuscle

BENCHMARK_MAIN();
