// SPDX-License-Identifier: Apache-2.0
#include "rbf_muscle.h"

#include <cstdio>
#include <limits>
#include <sstream>

#include "collision/bone_distance_grid.h"
#include "fibres/line_of_action.h"
#include "fit/surface_cache.h"
#include "geometry/mesh_distance.h"
#include "geometry/solid_mesh.h"
#include "model/attachment_areas.h"
#include "model/skeleton.h"
#include "pipeline/muscle_pipeline.h"

namespace rbfmuscle {
namespace {

/// A body's collision meshes, or its visual ones when it has none (an OpenSim model's bodies
/// carry geometry only). Each stays a bone of its own: the subject's ilium and sacrum overlap at
/// their joint, and the distance to the union of two solids is the smaller of their distances,
/// not the distance to their merged surfaces.
std::vector<const BodyMesh*> findCollisionMeshes(const Skeleton& skeleton, int body) {
  std::vector<const BodyMesh*> collision, visual;
  for (const BodyMesh& m : skeleton.getBodyMeshes(body)) (m.collision ? collision : visual).push_back(&m);
  return collision.empty() ? visual : collision;
}

/// One collision mesh in its body frame B (mm).
TriangleMesh loadMesh_B(const BodyMesh& mesh) {
  TriangleMesh part = loadSolidMesh(mesh.path);
  part.vertices_mm = mesh.X_BM * (mesh.scale_to_mm.asDiagonal() * part.vertices_mm);
  return part;
}

/// All points of the areas a spec names, in M (3×K).
Eigen::Matrix3Xd readArea_M(const Property<std::string>& spec, const InitContext& context, const Eigen::Vector3d& offset) {
  std::vector<Eigen::Vector3d> points;
  for (const AttachmentArea& area : parseAttachmentAreaSpec(spec.get(), context.getModelDirectory()))
    for (Eigen::Index j = 0; j < area.points_mm.cols(); ++j) points.push_back(area.points_mm.col(j) - offset);
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(points.size()));
  for (size_t j = 0; j < points.size(); ++j) m.col(static_cast<Eigen::Index>(j)) = points[j];
  return m;
}

/// Parses "x y z; x y z; …" (mm). @throws FrameworkError naming the property.
Eigen::Matrix3Xd parsePoints(const Property<std::string>& property) {
  std::vector<Eigen::Vector3d> points;
  std::stringstream groups(property.get());
  std::string group;
  while (std::getline(groups, group, ';')) {
    if (group.find_first_not_of(" \t\r\n") == std::string::npos) continue;
    std::istringstream fields(group);
    Eigen::Vector3d p;
    std::string extra;
    if (!(fields >> p.x() >> p.y() >> p.z()) || (fields >> extra) || !p.allFinite())
      throw FrameworkError(property.getName() + ": expected 'x y z; x y z; …' (mm), got '" + group + "'");
    points.push_back(p);
  }
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(points.size()));
  for (size_t j = 0; j < points.size(); ++j) m.col(static_cast<Eigen::Index>(j)) = points[j];
  return m;
}

}  // namespace

RBFMuscle::RBFMuscle()
    : fibre_lengths_output_(this, "fibre_length_mm", "mm", "length of each fibre",
                            [this]() -> const Eigen::VectorXd& { return pipeline_ ? pipeline_->getFibreLengths() : no_fibres_; }) {
  const std::vector<ReportField> fields = MusclePipeline::describeReports();
  report_values_.assign(fields.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < fields.size(); ++i)
    report_outputs_.push_back(std::make_unique<Output>(this, fields[i].name, fields[i].unit, fields[i].description,
                                                       [this, i] { return report_values_[i]; }));
}

RBFMuscle::~RBFMuscle() = default;

void RBFMuscle::initialize(const InitContext& context) {
  const Skeleton& skeleton = context.getSkeleton();
  FitSettings fit_settings;
  fit_settings.max_centres = centres.get();
  SurfaceOrigin origin = SurfaceOrigin::kCache;
  const RbfSurface surface = loadOrFitSurface(
      context.resolvePath(mesh_file.get()), surface_file.get().empty() ? "" : context.resolvePath(surface_file.get()),
      fit_settings, origin, [this](const std::string& line) { std::fprintf(stderr, "%s: %s\n", getName().c_str(), line.c_str()); });
  frame_offset_mm_ = surface.frame_offset_mm;
  const Eigen::Translation3d to_M(-frame_offset_mm_);

  MuscleDefinition muscle;
  muscle.rest_field = surface.field;
  muscle.rest_mesh_M = loadSolidMesh(context.resolvePath(mesh_file.get()));
  muscle.rest_mesh_M.vertices_mm.colwise() -= frame_offset_mm_;
  muscle.origin_area_M = readArea_M(origin_area, context, frame_offset_mm_);
  muscle.insertion_area_M = readArea_M(insertion_area, context, frame_offset_mm_);
  bone_bodies_ = {origin_body.getBodyIndex(), insertion_body.getBodyIndex()};
  X_GB_rest_ = {skeleton.getBodyTransform(bone_bodies_[0]), skeleton.getBodyTransform(bone_bodies_[1])};
  muscle.attachments = makeFreeAttachments(surface.field.getNumCentres(), 2);
  std::vector<AttachmentLandmark> landmarks;
  for (int bone = 0; bone < 2; ++bone) {
    const Eigen::Matrix3Xd& area = bone == 0 ? muscle.origin_area_M : muscle.insertion_area_M;
    for (Eigen::Index j = 0; j < area.cols(); ++j)
      landmarks.push_back(AttachmentLandmark{bone, area.col(j), attachment_radius_mm.get()});
  }
  attachByLandmarks(muscle.rest_field, landmarks, muscle.attachments);
  for (int bone = 0; bone < 2; ++bone)
    if (muscle.attachments.countAttachedTo(bone) == 0)
      throw FrameworkError(std::string(bone ? "insertion_area" : "origin_area") + ": no kernel centre lies within " +
                           "attachment_radius_mm of it; is the area on this muscle, in the mesh's frame?");
  attached_kernels_ = muscle.attachments.countAttached();

  contact_bodies_.clear();
  if (contacts.get())
    for (int body = 0; body < static_cast<int>(skeleton.getBodyNames().size()); ++body)
      for (const BodyMesh* mesh : findCollisionMeshes(skeleton, body)) {
        // One grid per mesh file and pose, shared by every muscle of the run.
        std::ostringstream key;
        key << mesh->path << '@' << mesh->X_BM.matrix().format(Eigen::IOFormat(17)) << mesh->scale_to_mm.transpose();
        std::shared_ptr<BoneDistanceGrid> grid = context.findOrMakeShared<BoneDistanceGrid>(
            key.str(), [&] { return std::make_shared<BoneDistanceGrid>(loadMesh_B(*mesh)); });
        contact_bodies_.push_back(body);
        muscle.bones.push_back(ClearanceBone{skeleton.getBodyNames()[static_cast<size_t>(body)], grid});
        muscle.rest_X_MB.push_back(to_M * skeleton.getBodyTransform(body));
      }

  PipelineSettings settings;
  settings.quadrature_points = quadrature_points.get();
  settings.descent.max_iterations = descent_iterations.get();
  settings.fibres = fibres.get();
  settings.fibre_segments = fibre_segments.get();
  settings.volume.max_correction = volume_max_correction.get();
  try {
    pipeline_ = std::make_unique<MusclePipeline>(muscle, settings);
  } catch (const std::invalid_argument& e) {
    throw FrameworkError(e.what());
  }

  Eigen::Matrix3Xd path_M = parsePoints(line_of_action_mm);
  if (path_M.cols() == 1) throw FrameworkError("line_of_action_mm: expected ≥ 2 points, got 1");
  if (path_M.cols() == 0) {  // the straight line between the areas' means
    path_M.resize(3, 2);
    path_M << muscle.origin_area_M.rowwise().mean(), muscle.insertion_area_M.rowwise().mean();
  } else {
    path_M.colwise() -= frame_offset_mm_;
  }
  line_of_action_ = std::make_unique<ViaPointPath>(makeViaPointPath(path_M, 0, 1, {}));
  bone_motion_M_.assign(2, Eigen::Isometry3d::Identity());
  declareInvariants(settings);
}

void RBFMuscle::declareInvariants(const PipelineSettings& settings) {
  const double infinity = std::numeric_limits<double>::infinity();
  const double volume_tolerance = settings.volume.tolerance;
  std::ostringstream volume;
  volume << "volume within the volume step's tolerance, |V/V_rest - 1| <= " << volume_tolerance;
  declareInvariant({"volume_ratio", 1.0 - volume_tolerance, 1.0 + volume_tolerance, volume.str()});
  declareInvariant({"volume_mm3", 0.0, infinity, "volume finite and positive"});
  declareInvariant({"line_of_action_length_mm", 0.0, infinity, "line of action finite"});
  if (settings.fibres > 0) declareInvariant({"fibre_length_mm", 0.0, infinity, "every fibre length finite and positive"});
  // The surface is tracked only for --frames-mesh (NaN otherwise). A vertex counts as found when
  // |min(f, s)| is within the surface tolerance, so none lies deeper in a bone than that.
  std::ostringstream depth;
  depth << "tracked surface no deeper in a bone than the surface tolerance, " << settings.surface.tolerance << " mm";
  declareInvariant({"surface_bone_depth_max_mm", -infinity, settings.surface.tolerance, depth.str(), true});
}

void RBFMuscle::update(const FrameState& state) {
  bool moved = state.getFrameIndex() == 0 || state.wantsGeometry();
  for (int body : bone_bodies_) moved = moved || state.hasBodyMoved(body);
  for (int body : contact_bodies_) moved = moved || state.hasBodyMoved(body);
  if (!moved) return;  // nothing this muscle depends on moved: the last frame stands
  const Eigen::Translation3d to_M(-frame_offset_mm_), from_M(frame_offset_mm_);
  FrameInput input;
  for (size_t b = 0; b < 2; ++b)
    bone_motion_M_[b] = to_M * state.getBodyTransform(bone_bodies_[b]) * X_GB_rest_[b].inverse() * from_M;
  X_MB_.resize(contact_bodies_.size());
  for (size_t b = 0; b < contact_bodies_.size(); ++b) X_MB_[b] = to_M * state.getBodyTransform(contact_bodies_[b]);
  input.bone_motion_M = bone_motion_M_;
  input.X_MB = X_MB_;
  input.want_surface = state.wantsGeometry();
  pipeline_->run(input);
  report_values_.clear();
  pipeline_->appendReports(report_values_);
  line_of_action_length_mm_ = calcPathLength(*line_of_action_, bone_motion_M_);
}

void RBFMuscle::appendFrameGeometry(std::vector<FrameGeometry>& geometry) const {
  const MuscleState& state = pipeline_->getState();
  Eigen::Matrix3Xd surface = state.surface_M.vertices_mm;
  surface.colwise() += frame_offset_mm_;
  geometry.push_back(FrameGeometry{getName(), std::move(surface), state.surface_M.triangles, {}});
  const RestFibres* rest = pipeline_->getRestFibres();
  if (!rest) return;
  Eigen::Matrix3Xd points = state.fibre_points_mm;
  points.colwise() += frame_offset_mm_;
  std::vector<std::vector<int>> polylines(static_cast<size_t>(rest->count));
  for (int i = 0; i < rest->count; ++i)
    for (int j = 0; j <= rest->segments; ++j) polylines[static_cast<size_t>(i)].push_back(i * (rest->segments + 1) + j);
  geometry.push_back(FrameGeometry{getName() + "_fibres", std::move(points), Eigen::Matrix3Xi(3, 0), std::move(polylines)});
}

}  // namespace rbfmuscle
