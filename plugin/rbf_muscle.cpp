// SPDX-License-Identifier: Apache-2.0
#include "rbf_muscle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "collision/bone_distance_grid.h"
#include "fibres/line_of_action.h"
#include "fit/surface_cache.h"
#include "geometry/mesh_distance.h"
#include "geometry/mesh_warning.h"
#include "geometry/move_out_of_solids.h"
#include "geometry/solid_mesh.h"
#include "model/attachment_areas.h"
#include "model/joint_centre.h"
#include "model/moment_arms.h"
#include "model/osim_muscle_path.h"
#include "model/skeleton.h"
#include "pipeline/muscle_pieces.h"
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

/// A collision mesh of the skeleton: its body and its distance grid.
struct BoneAtRest {
  int body = 0;
  std::shared_ptr<BoneDistanceGrid> grid;
  std::string file_name;
};

/// Every collision mesh of the skeleton (findCollisionMeshes), one grid per mesh file and pose,
/// shared by every muscle of the run. Built whether or not the muscle has contacts: its mesh is
/// moved out of them at rest either way.
std::vector<BoneAtRest> findBonesAtRest(const Skeleton& skeleton, const InitContext& context) {
  std::vector<BoneAtRest> bones;
  for (int body = 0; body < static_cast<int>(skeleton.getBodyNames().size()); ++body)
    for (const BodyMesh* mesh : findCollisionMeshes(skeleton, body)) {
      std::ostringstream key;
      key << mesh->path << '@' << mesh->X_BM.matrix().format(Eigen::IOFormat(17)) << mesh->scale_to_mm.transpose();
      bones.push_back(BoneAtRest{body, context.findOrMakeShared<BoneDistanceGrid>(
                                           key.str(), [&] { return std::make_shared<BoneDistanceGrid>(loadMesh_B(*mesh)); }),
                                 std::filesystem::path(mesh->path).filename().string()});
    }
  return bones;
}

/// Each point of an OpenSim muscle path at rest, in M (3×K).
Eigen::Matrix3Xd placeAtRest_M(const MusclePath& path, const Skeleton& skeleton, const Eigen::Vector3d& offset) {
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(path.points.size()));
  for (size_t i = 0; i < path.points.size(); ++i)
    points.col(static_cast<Eigen::Index>(i)) =
        skeleton.getBodyTransform(path.points[i].body) * path.points[i].location_B_mm - offset;
  return points;
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
  if (blend.get() != "distance" && blend.get() != "joint_angle")
    throw FrameworkError("blend: '" + blend.get() + "'; expected 'distance' or 'joint_angle'");
  const Skeleton& skeleton = context.getSkeleton();
  // The mesh lies in ground with the bones at the skeleton's rest pose; a part of it segmented
  // into a bone is moved out before the fit and the map see it (move_out_of_solids.h).
  const std::vector<BoneAtRest> bones = findBonesAtRest(skeleton, context);
  std::vector<PlacedSolid> solids;
  for (const BoneAtRest& bone : bones)
    solids.push_back(PlacedSolid{&bone.grid->getMeshDistance(), skeleton.getBodyTransform(bone.body), bone.file_name});
  const std::string mesh_path = context.resolvePath(mesh_file.get());
  TriangleMesh rest_mesh = loadSolidMesh(mesh_path);
  if (const std::string moved = describeMoveOut(mesh_path, moveOutOfSolids(rest_mesh, solids)); !moved.empty())
    printMeshWarning(moved);

  FitSettings fit_settings;
  fit_settings.max_centres = centres.get();
  SurfaceOrigin origin = SurfaceOrigin::kCache;
  const RbfSurface surface = loadOrFitSurface(
      mesh_path, surface_file.get().empty() ? "" : context.resolvePath(surface_file.get()), fit_settings, origin,
      [this](const std::string& line) { std::fprintf(stderr, "%s: %s\n", getName().c_str(), line.c_str()); },
      [&solids](TriangleMesh& mesh) { moveOutOfSolids(mesh, solids); });
  frame_offset_mm_ = surface.frame_offset_mm;
  const Eigen::Translation3d to_M(-frame_offset_mm_);

  MuscleDefinition muscle;
  muscle.rest_field = surface.field;
  muscle.rest_mesh_M = std::move(rest_mesh);
  muscle.rest_mesh_M.vertices_mm.colwise() -= frame_offset_mm_;
  muscle.origin_area_M = readArea_M(origin_area, context, false);
  muscle.insertion_area_M = readArea_M(insertion_area, context, true);
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
                           "attachment_radius_mm of it nearer to it than to the " + (bone ? "origin" : "insertion") +
                           " area; is the area on this muscle, in the mesh's frame?");
  attached_kernels_ = muscle.attachments.countAttached();

  contact_bodies_.clear();
  if (contacts.get())
    for (const BoneAtRest& bone : bones) {
      if (bone.body == bone_bodies_[0]) muscle.origin_bones.push_back(static_cast<int>(muscle.bones.size()));
      contact_bodies_.push_back(bone.body);
      muscle.bones.push_back(ClearanceBone{skeleton.getBodyNames()[static_cast<size_t>(bone.body)], bone.grid});
      muscle.rest_X_MB.push_back(to_M * skeleton.getBodyTransform(bone.body));
    }

  PipelineSettings settings;
  if (blend.get() == "joint_angle") settings.lattice.joint_centre_mm = findJointCentre_M(skeleton, muscle);
  settings.quadrature_points = volume_settings.quadrature_points.get();
  settings.descent.max_iterations = descent_settings.iterations.get();
  settings.fibres = fibre_settings.count.get();
  settings.lift_off = lift_off.get();
  settings.fibre_segments = fibre_settings.segments.get();
  settings.volume.max_correction = volume_settings.max_correction.get();
  try {
    pipeline_ = std::make_unique<MusclePipeline>(muscle, settings);
  } catch (const std::invalid_argument& e) {
    throw FrameworkError(e.what());
  }

  if (const double pulley = pipeline_->getPulleyWeight(); std::isfinite(pulley))
    std::fprintf(stderr, "%s: lifts off the joint when shortened, each fibre held up to blend weight %.3f (%s)\n",
                 getName().c_str(), pulley,
                 muscle.origin_bones.empty() ? "no contact bone on the origin body: held at the fibres' origin ends"
                                             : "the median where the fibres leave the origin body's bones at rest");
  if (const RestFibres* fibres = pipeline_->getRestFibres(); fibres && fibres->grid_refinements > 0)
    std::fprintf(stderr,
                 "%s: fibres routed on an interior grid of %.2f mm, refined %d times: the first split a part of "
                 "the muscle thinner than its spacing\n",
                 getName().c_str(), fibres->grid_spacing_mm, fibres->grid_refinements);
  makeLineOfAction(context, muscle.origin_area_M, muscle.insertion_area_M);
  makeMomentArmOutputs(skeleton);
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
  declareInvariant({"pieces", 1.0, 1.0, "the muscle in one piece (counted when check_pieces_cell_mm > 0)", true});
}

Eigen::Matrix3Xd RBFMuscle::readArea_M(const Property<std::string>& spec, const InitContext& context, bool last) const {
  Eigen::Matrix3Xd points;
  if (const std::optional<OsimMuscleReference> reference = parseOsimMuscleReference(spec.get())) {
    points.resize(3, static_cast<Eigen::Index>(reference->muscles.size()));
    for (size_t i = 0; i < reference->muscles.size(); ++i) {
      const MusclePath path = readOsimMusclePath(context.resolvePath(reference->file), reference->muscles[i], context.getSkeleton());
      const MusclePathPoint& end = last ? path.points.back() : path.points.front();
      points.col(static_cast<Eigen::Index>(i)) = context.getSkeleton().getBodyTransform(end.body) * end.location_B_mm;
    }
  } else {
    points = joinAreas(parseAttachmentAreaSpec(spec.get(), context.getModelDirectory()));
  }
  return points.colwise() - frame_offset_mm_;
}

Eigen::Vector3d RBFMuscle::findJointCentre_M(const Skeleton& skeleton, const MuscleDefinition& muscle) const {
  const std::string& from = skeleton.getBodyNames()[static_cast<size_t>(bone_bodies_[0])];
  const std::string& to = skeleton.getBodyNames()[static_cast<size_t>(bone_bodies_[1])];
  const Eigen::Vector3d centroid_G = muscle.rest_mesh_M.vertices_mm.rowwise().mean() + frame_offset_mm_;
  const std::optional<JointCentre> joint = findJointCentre(skeleton, bone_bodies_[0], bone_bodies_[1], centroid_G);
  if (!joint)
    throw FrameworkError("blend 'joint_angle': no rotational coordinate turns " + to + " relative to " + from +
                         "; use 'distance'");
  // A joint whose bodies also slide has no centre; 1 mm over the probes' 0.1 rad turns.
  if (joint->residual_mm > 1.0)
    throw FrameworkError("blend 'joint_angle': the joint between " + from + " and " + to + " moves any point by " +
                         std::to_string(joint->residual_mm) + " mm over a 0.1 rad turn: it has no centre; use 'distance'");
  const Eigen::Vector3d centre_M = joint->p_G_mm - frame_offset_mm_;
  const double angle_rad = calcAttachmentAngle(muscle.rest_field.getCentres(), muscle.attachments, centre_M);
  std::fprintf(stderr, "%s: blend by angle about the joint centre (%.2f %.2f %.2f) mm: the areas %.1f° apart, no fold up to %.1f°\n",
               getName().c_str(), joint->p_G_mm.x(), joint->p_G_mm.y(), joint->p_G_mm.z(), angle_rad * 180.0 / M_PI,
               calcFoldFreeTurn(angle_rad) * 180.0 / M_PI);
  return centre_M;
}

void RBFMuscle::makeLineOfAction(const InitContext& context, const Eigen::Matrix3Xd& origin_area_M,
                                 const Eigen::Matrix3Xd& insertion_area_M) {
  const Skeleton& skeleton = context.getSkeleton();
  ViaPointPath path;
  path_bodies_ = bone_bodies_;
  const auto addPathBody = [this](int body) {  // the path's bone index of a skeleton body
    const auto known = std::find(path_bodies_.begin(), path_bodies_.end(), body);
    if (known != path_bodies_.end()) return static_cast<int>(known - path_bodies_.begin());
    path_bodies_.push_back(body);
    return static_cast<int>(path_bodies_.size()) - 1;
  };
  try {
    if (line_of_action.get().find_first_not_of(" \t\r\n") == std::string::npos) {  // the areas' means
      Eigen::Matrix3Xd ends(3, 2);
      ends << origin_area_M.rowwise().mean(), insertion_area_M.rowwise().mean();
      path = makeViaPointPath(ends, 0, 1);
    } else if (const std::optional<OsimMuscleReference> reference = parseOsimMuscleReference(line_of_action.get())) {
      if (reference->muscles.size() != 1)
        throw FrameworkError("names " + std::to_string(reference->muscles.size()) + " muscles; expected one");
      const MusclePath muscle = readOsimMusclePath(context.resolvePath(reference->file), reference->muscles[0], skeleton);
      for (const std::string& note : muscle.notes) std::fprintf(stderr, "%s: line_of_action: %s\n", getName().c_str(), note.c_str());
      path.points_mm = placeAtRest_M(muscle, skeleton, frame_offset_mm_);
      path_bodies_.clear();
      for (const MusclePathPoint& point : muscle.points) {
        path.bones.push_back(addPathBody(point.body));
        path.conditions.push_back(PathPointCondition{point.coordinate, point.active_min, point.active_max});
      }
    } else {
      const ViaPointText text = splitViaPointBodies(line_of_action.get());
      const Eigen::Matrix3Xd points = joinAreas(parseAttachmentAreaSpec(text.points, context.getModelDirectory()));
      if (points.cols() < 2) throw FrameworkError("expected ≥ 2 points, got " + std::to_string(points.cols()));
      path = makeViaPointPath(points.colwise() - frame_offset_mm_, 0, 1);
      if (!text.bodies.empty()) {
        path_bodies_.clear();
        for (size_t i = 0; i < text.bodies.size(); ++i) {
          const int body = skeleton.findBodyIndex(text.bodies[i]);
          if (body < 0)
            throw FrameworkError("via point " + std::to_string(i + 1) + ": no body '" + text.bodies[i] + "' in the skeleton");
          path.bones[i] = addPathBody(body);
        }
      }
    }
  } catch (const std::exception& e) {
    throw FrameworkError("line_of_action: " + std::string(e.what()));
  }
  line_of_action_ = std::make_unique<ViaPointPath>(std::move(path));
  X_GB_path_rest_.clear();
  for (int body : path_bodies_) X_GB_path_rest_.push_back(skeleton.getBodyTransform(body));
}

void RBFMuscle::update(const FrameState& state) {
  bool moved = state.getFrameIndex() == 0 || state.wantsGeometry();
  for (int body : bone_bodies_) moved = moved || state.hasBodyMoved(body);
  for (int body : contact_bodies_) moved = moved || state.hasBodyMoved(body);
  for (int body : path_bodies_) moved = moved || state.hasBodyMoved(body);
  if (!moved) return;  // nothing this muscle depends on moved: the last frame stands
  if (moment_arms_) {
    // Every frame depends on its poses only, so probing poses either side leaves no trace.
    moment_arms_->update(state.getCoordinates(), [this](const Skeleton& posed, const Eigen::VectorXd& q) {
      runFrame([&](int body) { return posed.getBodyTransform(body); }, q, false);
      Eigen::VectorXd lengths(pipeline_->getFibreLengths().size() + 1);
      lengths << pipeline_->getFibreLengths(), line_of_action_length_mm_;
      return lengths;
    });
    const Eigen::Index fibre_count = pipeline_->getFibreLengths().size();
    for (size_t k = 0; k < moment_arms_->getCoordinates().size(); ++k) {
      const Eigen::VectorXd& arms = moment_arms_->getArms(k);
      fibre_moment_arms_mm_[k] = arms.head(fibre_count);
      fibre_moment_arm_mean_mm_[k] = fibre_count ? arms.head(fibre_count).mean() : std::numeric_limits<double>::quiet_NaN();
      line_of_action_moment_arm_mm_[k] = arms[fibre_count];
    }
  }
  runFrame([&](int body) { return state.getBodyTransform(body); }, state.getCoordinates(), state.wantsGeometry());
  report_values_.clear();
  pipeline_->appendReports(report_values_);
  if (check_pieces_cell_mm.get() > 0.0) {
    const MusclePieces pieces = countMusclePieces(pipeline_->getState(), check_pieces_cell_mm.get());
    pieces_ = pieces.pieces;
    stray_volume_mm3_ = pieces.stray_volume_mm3;
    stray_centre_G_mm_ = pieces.stray_centre_mm + frame_offset_mm_;
  }
}

void RBFMuscle::runFrame(const std::function<Eigen::Isometry3d(int)>& X_GB, const Eigen::VectorXd& q, bool want_surface) {
  const Eigen::Translation3d to_M(-frame_offset_mm_), from_M(frame_offset_mm_);
  FrameInput input;
  for (size_t b = 0; b < 2; ++b) bone_motion_M_[b] = to_M * X_GB(bone_bodies_[b]) * X_GB_rest_[b].inverse() * from_M;
  X_MB_.resize(contact_bodies_.size());
  for (size_t b = 0; b < contact_bodies_.size(); ++b) X_MB_[b] = to_M * X_GB(contact_bodies_[b]);
  input.bone_motion_M = bone_motion_M_;
  input.X_MB = X_MB_;
  input.want_surface = want_surface;
  pipeline_->run(input);
  path_motion_M_.resize(path_bodies_.size());
  for (size_t b = 0; b < path_bodies_.size(); ++b)
    path_motion_M_[b] = to_M * X_GB(path_bodies_[b]) * X_GB_path_rest_[b].inverse() * from_M;
  line_of_action_length_mm_ = calcPathLength(*line_of_action_, path_motion_M_, q);
}

void RBFMuscle::makeMomentArmOutputs(const Skeleton& skeleton) {
  const std::vector<int> coordinates = parseCoordinateList(moment_arms.get(), skeleton);
  if (coordinates.empty()) return;
  moment_arms_ = std::make_unique<MomentArms>(skeleton, coordinates);
  const size_t n = coordinates.size();
  fibre_moment_arm_mean_mm_.assign(n, std::numeric_limits<double>::quiet_NaN());
  line_of_action_moment_arm_mm_.assign(n, std::numeric_limits<double>::quiet_NaN());
  fibre_moment_arms_mm_.assign(n, Eigen::VectorXd::Constant(fibre_settings.count.get(), std::numeric_limits<double>::quiet_NaN()));
  for (size_t k = 0; k < n; ++k) {
    const std::string& name = skeleton.getCoordinateNames()[static_cast<size_t>(coordinates[k])];
    const std::string per = skeleton.getCoordinates()[static_cast<size_t>(coordinates[k])].motion ==
                                    CoordinateMotion::kRotational ? "mm per rad" : "mm per mm";
    moment_arm_outputs_.push_back(std::make_unique<Output>(
        this, "moment_arm_" + name + "_mm", "mm", "mean over fibres of the moment arm −∂l/∂q about " + name + " (" + per + ")",
        [this, k] { return fibre_moment_arm_mean_mm_[k]; }));
    moment_arm_outputs_.push_back(std::make_unique<Output>(
        this, "line_of_action_moment_arm_" + name + "_mm", "mm", "moment arm of the line of action about " + name + " (" + per + ")",
        [this, k] { return line_of_action_moment_arm_mm_[k]; }));
    moment_arm_outputs_.push_back(std::make_unique<VectorOutput>(
        this, "fibre_moment_arm_" + name + "_mm", "mm", "moment arm of each fibre about " + name + " (" + per + ")",
        [this, k]() -> const Eigen::VectorXd& { return fibre_moment_arms_mm_[k]; }));
  }
}

void RBFMuscle::appendFrameGeometry(std::vector<FrameGeometry>& geometry) const {
  const MuscleState& state = pipeline_->getState();
  Eigen::Matrix3Xd surface = state.surface_M.vertices_mm;
  surface.colwise() += frame_offset_mm_;
  geometry.push_back(FrameGeometry{getName(), std::move(surface), state.surface_M.triangles, {}});
  const RestFibres* rest = pipeline_->getRestFibres();
  if (!rest) return;
  // Each fibre from its origin attachment through its points to its insertion attachment.
  const Eigen::Index inside = state.fibre_points_mm.cols();
  Eigen::Matrix3Xd points(3, inside + state.fibre_attachments_mm.cols());
  points << state.fibre_points_mm, state.fibre_attachments_mm;
  points.colwise() += frame_offset_mm_;
  std::vector<std::vector<int>> polylines(static_cast<size_t>(rest->count));
  for (int i = 0; i < rest->count; ++i) {
    std::vector<int>& line = polylines[static_cast<size_t>(i)];
    line.push_back(static_cast<int>(inside) + 2 * i);
    for (int j = 0; j <= rest->segments; ++j) line.push_back(i * (rest->segments + 1) + j);
    line.push_back(static_cast<int>(inside) + 2 * i + 1);
  }
  geometry.push_back(FrameGeometry{getName() + "_fibres", std::move(points), Eigen::Matrix3Xi(3, 0), std::move(polylines)});
}

}  // namespace rbfmuscle
