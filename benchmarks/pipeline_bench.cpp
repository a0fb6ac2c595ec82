// SPDX-License-Identifier: Apache-2.0
// One muscle's frame through the pipeline (core/pipeline) on the hip data: the gluteus maximus
// (1000 kernels) and the iliacus (2000) over flexion, with the subject's femur, ilium and
// sacrum as contact bones; and how the frame's cost grows with quadrature points and kernels. A frame is a
// function of its pose, so the benchmark cycles through the angles 0…80°.
#include "collision/bone_distance_grid.h"
#include "fit/fit_pipeline.h"
#include "fit/rbf_file.h"
#include "geometry/mesh_io.h"
#include "model/attachment_areas.h"
#include "pipeline/muscle_pipeline.h"

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <map>
#include <memory>
#include <string>

namespace rbfmuscle {
namespace {

const std::string kHip = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip/";

/// Right-hip flexion axis (+Z of the pelvis frame) and centre, CT frame (landmarks/hip_frame.json).
const Eigen::Vector3d kAxis(-0.9924778435393229, 0.11879490607095865, 0.029588855590025775);
const Eigen::Vector3d kHipCentre(143.225, 243.37, -432.499);

struct Muscle {
  std::unique_ptr<MusclePipeline> pipeline;
  Eigen::Vector3d offset;
};

Eigen::Matrix3Xd readArea(const std::string& clouds, const Eigen::Vector3d& offset) {
  Eigen::Matrix3Xd all(3, 0);
  for (const AttachmentArea& a : parseAttachmentAreaSpec("landmarks/attachment_areas.json: " + clouds, kHip)) {
    all.conservativeResize(3, all.cols() + a.points_mm.cols());
    all.rightCols(a.points_mm.cols()) = a.points_mm.colwise() - offset;
  }
  return all;
}

/// The muscle's pipeline from `surface` (its stored fit unless given).
Muscle makeMuscle(const std::string& mesh, const std::string& origin, const std::string& insertion, int quadrature,
                  const RbfSurface* fitted = nullptr) {
  static std::map<std::string, std::shared_ptr<BoneDistanceGrid>> grids;  // shared, as in a run
  const RbfSurface surface = fitted ? *fitted : readRbfFile(kHip + "surfaces/" + mesh + ".rbf");
  MuscleDefinition d;
  d.rest_field = surface.field;
  d.rest_mesh_M = loadMesh(kHip + "meshes/" + mesh + ".ply");
  d.rest_mesh_M.vertices_mm.colwise() -= surface.frame_offset_mm;
  d.origin_area_M = readArea(origin, surface.frame_offset_mm);
  d.insertion_area_M = readArea(insertion, surface.frame_offset_mm);
  d.attachments = makeFreeAttachments(surface.field.getNumCentres(), 2);
  std::vector<AttachmentLandmark> landmarks;
  for (Eigen::Index j = 0; j < d.origin_area_M.cols(); ++j) landmarks.push_back({0, d.origin_area_M.col(j), 10.0});
  for (Eigen::Index j = 0; j < d.insertion_area_M.cols(); ++j) landmarks.push_back({1, d.insertion_area_M.col(j), 10.0});
  attachByLandmarks(d.rest_field, landmarks, d.attachments);
  for (const std::string bone : {"femur_r", "pelvis_iliac_r", "pelvis_sacrum"}) {
    std::shared_ptr<BoneDistanceGrid>& grid = grids[bone];
    if (!grid) grid = std::make_shared<BoneDistanceGrid>(loadMesh(kHip + "meshes/" + bone + ".ply"));
    d.bones.push_back({bone, grid});
    d.rest_X_MB.push_back(Eigen::Isometry3d(Eigen::Translation3d(-surface.frame_offset_mm)));
  }
  PipelineSettings settings;
  settings.quadrature_points = quadrature;
  return Muscle{std::make_unique<MusclePipeline>(d, settings), surface.frame_offset_mm};
}

FrameInput flexion(double degrees, const Eigen::Vector3d& offset) {
  const Eigen::Vector3d c = kHipCentre - offset;
  const Eigen::Isometry3d femur(Eigen::Translation3d(c) * Eigen::AngleAxisd(degrees * M_PI / 180.0, kAxis) *
                                Eigen::Translation3d(-c));
  FrameInput input;
  input.bone_motion_M = {Eigen::Isometry3d::Identity(), femur};
  const Eigen::Isometry3d pelvis(Eigen::Translation3d(-offset));
  input.X_MB = {femur * pelvis, pelvis, pelvis};
  return input;
}

void runFrames(benchmark::State& state, Muscle& muscle) {
  int degrees = 0;
  for (auto _ : state) {
    muscle.pipeline->run(flexion(degrees, muscle.offset));
    degrees = (degrees + 1) % 81;
  }
  std::vector<double> values;
  muscle.pipeline->appendReports(values);
  const std::vector<ReportField> fields = MusclePipeline::describeReports();
  for (size_t i = 0; i < fields.size(); ++i)
    if (fields[i].unit == "ms") state.counters[fields[i].name] = values[i];
}

void BM_GluteusFrame(benchmark::State& state) {
  static Muscle m = makeMuscle("gluteus_maximus_r", "LC_SET_Ori_1_R_M081_Glut_Max, LC_SET_Ori_2_R_M081_Glut_Max",
                               "LC_SET_Ins_1_R_M081_Glut_Max, LC_SET_Ins_2_R_M081_Glut_Max", 2000);
  runFrames(state, m);
}
BENCHMARK(BM_GluteusFrame)->Unit(benchmark::kMillisecond);

void BM_IliacusFrame(benchmark::State& state) {
  static Muscle m = makeMuscle("iliacus_r", "LC_SET_Ori_1_R_M091_Iliacus", "LC_SET_Ins_1_R_M091_Iliacus", 2000);
  runFrames(state, m);
}
BENCHMARK(BM_IliacusFrame)->Unit(benchmark::kMillisecond);

/// Cost against quadrature points (the volume measure and the descent's subset grow together).
void BM_IliacusFrameByQuadrature(benchmark::State& state) {
  Muscle m = makeMuscle("iliacus_r", "LC_SET_Ori_1_R_M091_Iliacus", "LC_SET_Ins_1_R_M091_Iliacus",
                        static_cast<int>(state.range(0)));
  runFrames(state, m);
}
BENCHMARK(BM_IliacusFrameByQuadrature)->Arg(1000)->Arg(2000)->Arg(4000)->Arg(8000)->Unit(benchmark::kMillisecond);

/// Cost against kernels: the gluteus fitted with 250 … 2000 kernels (the fit, done once per
/// count, is not timed).
void BM_GluteusFrameByCentres(benchmark::State& state) {
  FitSettings settings;
  settings.max_centres = static_cast<int>(state.range(0));
  const MeshFit fit = fitMeshFile(kHip + "meshes/gluteus_maximus_r.ply", settings, false);
  Muscle m = makeMuscle("gluteus_maximus_r", "LC_SET_Ori_1_R_M081_Glut_Max, LC_SET_Ori_2_R_M081_Glut_Max",
                        "LC_SET_Ins_1_R_M081_Glut_Max, LC_SET_Ins_2_R_M081_Glut_Max", 2000, &fit.surface);
  runFrames(state, m);
  state.counters["jaccard"] = fit.metrics.jaccard;
}
BENCHMARK(BM_GluteusFrameByCentres)->Arg(250)->Arg(500)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rbfmuscle

BENCHMARK_MAIN();
