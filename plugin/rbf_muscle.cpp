#include "rbf_muscle.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "collision/contact_resolver.h"
#include "collision/screw_interpolation.h"
#include "collision/surface_probes.h"
#include "dynamics/attachment.h"
#include "dynamics/muscle_deformer.h"
#include "fibres/fibre_generator.h"
#include "fibres/fibre_tracker.h"
#include "fibres/line_of_action.h"
#include "fit/surface_cache.h"
#include "geometry/mesh_distance.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_region.h"
#include "geometry/solid_mesh.h"
#include "model/skeleton.h"

namespace rbfmuscle {
namespace {

/// Parses "x y z; x y z; …" (mm). @throws FrameworkError naming the property.
std::vector<Eigen::Vector3d> parseLandmarks(const std::string& text, const std::string& property) {
  std::vector<Eigen::Vector3d> points;
  std::stringstream groups(text);
  std::string group;
  while (std::getline(groups, group, ';')) {
    if (group.find_first_not_of(" \t\r\n") == std::string::npos) continue;
    std::istringstream fields(group);
    Eigen::Vector3d p;
    std::string extra;
    if (!(fields >> p.x() >> p.y() >> p.z()) || (fields >> extra) || !p.allFinite())
      throw FrameworkError(property + ": expected 'x y z; x y z; …' (mm), got '" + group + "'");
    points.push_back(p);
  }
  return points;
}

/// A body's collision meshes (visual ones if it has none) in a frame F given by X_FB (mm);
/// empty when the body has no mesh. Each part is loaded as a solid (repaired where safe,
/// with a warning; MeshError naming the file when it does not bound one) and moved by
/// X_FB·X_BM in one product.
TriangleMesh loadBoneMesh(const Skeleton& skeleton, int body, const Eigen::Isometry3d& X_FB) {
  const std::vector<BodyMesh>& meshes = skeleton.getBodyMeshes(body);
  bool any_collision = false;
  for (const BodyMesh& m : meshes) any_collision |= m.collision;
  TriangleMesh all;
  for (const BodyMesh& m : meshes) {
    if (m.collision != any_collision) continue;
    TriangleMesh part = loadSolidMesh(m.path);
    const Eigen::Matrix3Xd v = (X_FB * m.X_BM) * (m.scale_to_mm.asDiagonal() * part.vertices_mm);
    const Eigen::Index base = all.vertices_mm.cols();
    all.vertices_mm.conservativeResize(3, base + v.cols());
    all.vertices_mm.rightCols(v.cols()) = v;
    all.triangles.conservativeResize(3, all.triangles.cols() + part.triangles.cols());
    all.triangles.rightCols(part.triangles.cols()) = part.triangles.array() + static_cast<int>(base);
  }
  return all;
}

/// The meshes in the body frame B.
TriangleMesh loadBoneMesh_B(const Skeleton& skeleton, int body) {
  return loadBoneMesh(skeleton, body, Eigen::Isometry3d::Identity());
}

/// The meshes at rest in M (the ground frame shifted by `offset_mm`).
/// @throws FrameworkError naming `needed_by` (the property) when the body has no mesh.
TriangleMesh loadBoneMesh_M(const Skeleton& skeleton, int body, const Eigen::Vector3d& offset_mm,
                            const std::string& needed_by) {
  TriangleMesh mesh = loadBoneMesh(skeleton, body, skeleton.getBodyTransform(body));
  if (mesh.countTriangles() == 0)
    throw FrameworkError(needed_by + " needs a mesh on body '" + skeleton.getBodyNames()[body] +
                         "' in " + skeleton.getUrdfPath());
  mesh.vertices_mm.colwise() -= offset_mm;
  return mesh;
}

/// Points as a 3×K matrix.
Eigen::Matrix3Xd toMatrix(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(points.size()));
  for (size_t k = 0; k < points.size(); ++k) m.col(static_cast<Eigen::Index>(k)) = points[k];
  return m;
}

/// Region marking one attachment (M): its landmarks, or the centres attached to `bone`.
Eigen::Matrix3Xd findAttachmentRegion(const std::vector<Eigen::Vector3d>& landmarks_M, const GaussianField& field,
                                      const Attachments& attachments, int bone) {
  if (!landmarks_M.empty()) return toMatrix(landmarks_M);
  std::vector<Eigen::Vector3d> centres;
  for (int k = 0; k < field.getNumCentres(); ++k)
    if (attachments.bone_of_centre[static_cast<size_t>(k)] == bone) centres.push_back(field.getCentres().col(k));
  return toMatrix(centres);
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

RBFMuscle::RBFMuscle() = default;
RBFMuscle::~RBFMuscle() = default;

void RBFMuscle::initialize(const InitContext& context) {
  const Skeleton& skeleton = context.getSkeleton();
  const std::string mesh_path = context.resolvePath(mesh_file.get());
  const std::string cache_path = surface_file.get().empty() ? "" : context.resolvePath(surface_file.get());
  FitSettings fit_settings;
  fit_settings.max_centres = centres.get();
  SurfaceOrigin origin = SurfaceOrigin::kCache;
  const RbfSurface surface = loadOrFitSurface(mesh_path, cache_path, fit_settings, origin,
                                              [this](const std::string& line) {
                                                std::fprintf(stderr, "%s: %s\n", getName().c_str(), line.c_str());
                                              });
  frame_offset_mm_ = surface.frame_offset_mm;

  // Bones 0 (origin) and 1 (insertion), poses at rest (the skeleton is at rest now).
  const std::vector<int> bodies = {origin_body.getBodyIndex(), insertion_body.getBodyIndex()};
  X_GB_rest_.clear();
  for (int body : bodies) X_GB_rest_.push_back(skeleton.getBodyTransform(body));
  bone_motion_M_.assign(bodies.size(), Eigen::Isometry3d::Identity());

  const GaussianField& field = surface.field;
  Attachments attachments = makeFreeAttachments(field.getNumCentres(), static_cast<int>(bodies.size()));
  std::vector<AttachmentLandmark> landmarks;
  const std::pair<const Property<std::string>*, int> lists[] = {{&origin_landmarks_mm, 0}, {&insertion_landmarks_mm, 1}};
  for (const auto& [property, bone] : lists)
    for (const Eigen::Vector3d& p_G : parseLandmarks(property->get(), property->getName()))
      landmarks.push_back(AttachmentLandmark{bone, p_G - frame_offset_mm_, landmark_radius_mm.get()});
  attachByLandmarks(field, landmarks, attachments);
  const std::string& support = supporting_bodies.get();
  if (support != "none" && support != "origin" && support != "insertion" && support != "both")
    throw FrameworkError("supporting_bodies: expected origin, insertion, both or none, got '" + support + "'");
  // Each bone's rest surface in M, loaded once for proximity_mm and supporting_bodies.
  std::shared_ptr<const MeshDistance> surfaces_M[2];
  const auto boneSurface = [&](int bone, const char* needed_by) {
    if (!surfaces_M[bone])
      surfaces_M[bone] = std::make_shared<const MeshDistance>(loadBoneMesh_M(skeleton, bodies[bone], frame_offset_mm_, needed_by));
    return surfaces_M[bone];
  };
  if (proximity_mm.get() > 0) {
    const std::vector<const MeshDistance*> bones_M = {boneSurface(0, "proximity_mm > 0").get(),
                                                      boneSurface(1, "proximity_mm > 0").get()};
    attachByProximity(field, bones_M, proximity_mm.get(), 1.0, attachments);
  }
  for (int bone = 0; bone < 2; ++bone) {
    if (support != "both" && support != (bone == 0 ? "origin" : "insertion")) continue;
    std::shared_ptr<const MeshDistance> surface = boneSurface(bone, "supporting_bodies");
    if (support_radius_mm.get() > 0) {
      std::vector<Eigen::Vector3d> own;
      for (const AttachmentLandmark& l : landmarks)
        if (l.bone == bone) own.push_back(l.p_M_mm);
      TriangleMesh near = keepTrianglesNear(surface->getMesh(), findAttachmentRegion(own, field, attachments, bone),
                                            support_radius_mm.get());
      if (near.countTriangles() == 0)
        throw FrameworkError("support_radius_mm = " + (std::ostringstream() << support_radius_mm.get()).str() +
                             " mm: no triangle of body '" +
                             skeleton.getBodyNames()[static_cast<size_t>(bodies[bone])] + "' lies within it of the " +
                             (bone ? "insertion" : "origin") + " (its landmarks, else its attached centres)");
      surface = std::make_shared<const MeshDistance>(std::move(near));
    }
    addSupport(bone, std::move(surface), attachments);
  }
  for (int bone = 0; bone < 2; ++bone)
    if (attachments.countAttachedTo(bone) == 0)
      throw FrameworkError(std::string("no centre attaches to the ") + (bone ? "insertion" : "origin") +
                           " body: give " + (bone ? "insertion" : "origin") +
                           "_landmarks_mm near the muscle, a larger landmark_radius_mm, or proximity_mm");
  result_.attached_centres = attachments.countAttached();

  DeformerSettings settings;
  settings.quadrature.target_count = quadrature_points.get();
  settings.descent.max_iterations = max_iterations.get();
  settings.descent.cost_tolerance = cost_tolerance.get();
  settings.descent.regularisation = regularisation.get();
  settings.volume.enabled = keep_volume.get();
  settings.volume.tolerance = volume_tolerance.get();
  settings.topology.neck_level = neck_level.get();
  settings.topology.crumb_join_level = crumb_join_level.get();
  settings.step_limit.max_step_mm = max_surface_step_mm.get();
  settings.step_limit.cell_mm = surface_cell_mm.get();
  deformer_ = std::make_unique<MuscleDeformer>(field, attachments, settings);
  initializeFibres(skeleton, field, attachments, settings.blend_length_mm);
  initializeContacts(skeleton);
  previous_motion_M_ = bone_motion_M_;
}

void RBFMuscle::initializeContacts(const Skeleton& skeleton) {
  contact_resolver_.reset();
  contact_field_.reset();
  contact_bodies_.clear();
  if (contact_probes.get() == 0) return;
  const Eigen::Translation3d to_M(-frame_offset_mm_);
  std::vector<ContactBone> bones;
  for (int body = 0; body < static_cast<int>(skeleton.getBodyNames().size()); ++body) {
    TriangleMesh mesh_B = loadBoneMesh_B(skeleton, body);
    if (mesh_B.countTriangles() == 0) continue;
    contact_bodies_.push_back(body);
    bones.push_back(ContactBone{skeleton.getBodyNames()[static_cast<size_t>(body)], std::move(mesh_B),
                                Eigen::Isometry3d(to_M * skeleton.getBodyTransform(body))});
  }
  if (bones.empty()) throw FrameworkError("contact_probes > 0 but no body of " + skeleton.getUrdfPath() + " has a mesh");
  previous_X_MB_.clear();
  for (const ContactBone& bone : bones) previous_X_MB_.push_back(bone.X_MB_rest);
  const GaussianField& field = deformer_->getField();
  rest_probes_M_ = sampleSurfaceProbes(deformer_->extractSurface(surface_cell_mm.get()), contact_probes.get());
  const Attachments& attachments = deformer_->getAttachments();
  probe_weights_ = calcBlendWeights(rest_probes_M_, field.getCentres(), attachments, DeformerSettings{}.blend_length_mm);
  std::vector<bool> free_centres(static_cast<size_t>(field.getNumCentres()));
  for (int k = 0; k < field.getNumCentres(); ++k) free_centres[static_cast<size_t>(k)] = !attachments.isAttached(k);
  ContactSettings settings;
  settings.tolerance_mm = contact_tolerance_mm.get();
  settings.max_substeps = max_substeps.get();
  settings.max_iterations = contact_iterations_cap.get();
  settings.max_reseats = contact_max_reseats.get();
  try {
    contact_resolver_ = std::make_unique<ContactResolver>(std::move(bones), field, rest_probes_M_, std::move(free_centres),
                                                          settings);
  } catch (const std::exception& e) {
    throw FrameworkError(std::string("contacts: ") + e.what());
  }
  contact_field_ = std::make_unique<GaussianField>(field);
}

void RBFMuscle::initializeFibres(const Skeleton& skeleton, const GaussianField& field, const Attachments& attachments,
                                 double blend_length_mm) {
  fibre_tracker_.reset();
  result_.fiber_lengths_mm.resize(0);
  std::vector<Eigen::Vector3d> landmarks_M[2];
  const Property<std::string>* lists[] = {&origin_landmarks_mm, &insertion_landmarks_mm};
  for (int bone = 0; bone < 2; ++bone)
    for (const Eigen::Vector3d& p_G : parseLandmarks(lists[bone]->get(), lists[bone]->getName()))
      landmarks_M[bone].push_back(p_G - frame_offset_mm_);
  const Eigen::Matrix3Xd regions[2] = {findAttachmentRegion(landmarks_M[0], field, attachments, 0),
                                       findAttachmentRegion(landmarks_M[1], field, attachments, 1)};
  if (fibres.get() > 0) {
    FibreSettings fibre_settings;
    fibre_settings.count = fibres.get();
    fibre_settings.segments = fibre_segments.get();
    try {
      const RestFibres rest = generateFibres(field, regions[0], regions[1], fibre_settings);
      fibre_tracker_ = std::make_unique<FibreTracker>(rest, field.getCentres(), attachments, 0, 1, blend_length_mm,
                                                      fibre_settings.projection);
    } catch (const std::exception& e) {
      throw FrameworkError(std::string("fibres: ") + e.what());
    }
    result_.fiber_lengths_mm = fibre_tracker_->getRest().lengths_mm;
  }
  line_of_action_.reset();
  const std::vector<Eigen::Vector3d> path_G = parseLandmarks(line_of_action_mm.get(), line_of_action_mm.getName());
  if (path_G.size() == 1) throw FrameworkError("line_of_action_mm: expected ≥ 2 points, got 1");
  if (path_G.empty()) {  // straight line between the mean attachment points (class comment)
    Eigen::Matrix3Xd ends(3, 2);
    ends << regions[0].rowwise().mean(), regions[1].rowwise().mean();
    line_of_action_ = std::make_unique<ViaPointPath>(ViaPointPath{ends, {0, 1}});
    return;
  }
  Eigen::Matrix3Xd path_M = toMatrix(path_G);
  path_M.colwise() -= frame_offset_mm_;
  std::vector<MeshDistance> bone_distance;
  try {
    for (int body : {origin_body.getBodyIndex(), insertion_body.getBodyIndex()})
      bone_distance.emplace_back(loadBoneMesh_M(skeleton, body, frame_offset_mm_, "line_of_action_mm"));
  } catch (const FrameworkError&) {
    bone_distance.clear();  // a body without mesh: intermediate points by arc length (class comment)
  }
  std::vector<const MeshDistance*> bones_M;
  for (const MeshDistance& d : bone_distance) bones_M.push_back(&d);
  line_of_action_ = std::make_unique<ViaPointPath>(makeViaPointPath(path_M, 0, 1, bones_M));
}

void RBFMuscle::update(const FrameState& state) {
  const auto start = std::chrono::steady_clock::now();
  // Bone motion since rest, X_GB(q)·X_GB(0)⁻¹, expressed in M (ground shifted by the offset).
  const Eigen::Translation3d to_M(-frame_offset_mm_), from_M(frame_offset_mm_);
  const int bodies[] = {origin_body.getBodyIndex(), insertion_body.getBodyIndex()};
  for (std::size_t b = 0; b < bone_motion_M_.size(); ++b)
    bone_motion_M_[b] = to_M * state.getBodyTransform(bodies[b]) * X_GB_rest_[b].inverse() * from_M;
  X_MB_.resize(contact_bodies_.size());
  for (std::size_t b = 0; b < contact_bodies_.size(); ++b)
    X_MB_[b] = to_M * state.getBodyTransform(contact_bodies_[b]);
  result_.collision_ms = contact_resolver_ ? 0.0 : DeformResult::kNaN;
  result_.max_penetration_mm = result_.max_penetration_before_mm = result_.contacts = DeformResult::kNaN;
  result_.max_penetration_free_mm = result_.max_penetration_watched_mm = DeformResult::kNaN;
  result_.probes_off_surface = result_.probes_reseated = contact_resolver_ ? 0.0 : DeformResult::kNaN;
  result_.contact_iterations = 0;
  int steps = 1;
  const bool carried = contact_resolver_ && contact_response.get();  // the probes at the frame's motion, below
  if (carried) {  // sub-steps guard tunnelling of the response only
    const auto t = std::chrono::steady_clock::now();
    carryProbes(bone_motion_M_);
    steps = contact_resolver_->calcSubsteps(X_MB_, carried_probes_M_);
    result_.collision_ms += msSince(t);
  }
  result_.substeps = steps;
  double descent_ms = 0.0, predict_ms = 0.0, volume_ms = 0.0, guard_ms = 0.0, islands = 0.0;
  double step_excess_mm = 0.0, step_scale = 1.0, step_excess_left_mm = 0.0;
  for (int s = 1; s <= steps; ++s) {
    if (s == steps) {
      step(bone_motion_M_, X_MB_, carried && steps == 1);
    } else {
      const double fraction = static_cast<double>(s) / steps;
      step_motion_M_.resize(bone_motion_M_.size());
      step_X_MB_.resize(X_MB_.size());
      for (std::size_t b = 0; b < bone_motion_M_.size(); ++b)
        step_motion_M_[b] = interpolateScrew(previous_motion_M_[b], bone_motion_M_[b], fraction);
      for (std::size_t b = 0; b < X_MB_.size(); ++b)
        step_X_MB_[b] = interpolateScrew(previous_X_MB_[b], X_MB_[b], fraction);
      step(step_motion_M_, step_X_MB_);
    }
    const DeformResult& sub = deformer_->getResult();
    descent_ms += sub.descent_ms;
    predict_ms += sub.predict_ms;
    volume_ms += sub.volume_ms;
    guard_ms += sub.topology_ms;
    islands += sub.islands_found;
    step_excess_mm = std::max(step_excess_mm, sub.step_limit.full_excess_mm);
    step_scale = std::min(step_scale, sub.step_limit.scale);
    step_excess_left_mm = std::max(step_excess_left_mm, sub.step_limit.excess_mm);
  }
  previous_motion_M_ = bone_motion_M_;
  previous_X_MB_ = X_MB_;
  const DeformResult& r = deformer_->getResult();
  result_.volume_mm3 = r.volume_mm3;
  result_.volume_ratio = r.volume_ratio;
  result_.volume_correction = r.volume_correction;
  result_.curvature_cost = r.curvature_cost;
  result_.iterations = r.iterations;
  result_.descent_ms = descent_ms;
  result_.predict_ms = predict_ms;
  result_.volume_ms = volume_ms;
  result_.guard_ms = guard_ms;
  result_.islands_removed = islands;
  result_.islands_left = r.islands_left;
  result_.step_excess_mm = step_excess_mm;
  result_.step_scale = step_scale;
  result_.step_excess_left_mm = step_excess_left_mm;
  if (fibre_tracker_) {
    const FibreFrame& f = fibre_tracker_->update(deformer_->getField(), bone_motion_M_);
    result_.fiber_lengths_mm = f.lengths_mm;
    result_.fiber_length_mean_mm = f.mean_mm;
    result_.fiber_length_min_mm = f.min_mm;
    result_.fiber_length_max_mm = f.max_mm;
    result_.fiber_length_normalised = f.normalised_mean;
    result_.fiber_projections = f.projected;
    result_.fiber_points_outside = f.outside;
    result_.fiber_end_offset_max_mm = f.end_offset_max_mm;
  }
  if (line_of_action_) result_.line_of_action_length_mm = calcPathLength(*line_of_action_, bone_motion_M_);
  result_.update_ms = msSince(start);
}

void RBFMuscle::step(const std::vector<Eigen::Isometry3d>& motion_M, const std::vector<Eigen::Isometry3d>& X_MB,
                     bool probes_carried) {
  deformer_->update(motion_M);
  if (!contact_resolver_) return;
  const auto start = std::chrono::steady_clock::now();
  if (!probes_carried) carryProbes(motion_M);
  const GaussianField& field = deformer_->getField();
  const ContactReport* measured = nullptr;
  if (contact_response.get()) {  // a push moves centres of a copy (made only then), handed back to the deformer
    measured = &contact_resolver_->resolveFrom(X_MB, carried_probes_M_, field, *contact_field_);
    if (measured->moved_centres > 0) deformer_->applyKeptCorrection(contact_field_->getCentres());
  } else {  // measuring reads the deformer's field itself
    measured = &contact_resolver_->measureOnly(X_MB, carried_probes_M_, field);
  }
  const ContactReport& report = *measured;
  const auto maxOrNaN = [](double a, double b) { return std::isnan(a) ? b : std::max(a, b); };
  result_.max_penetration_mm = maxOrNaN(result_.max_penetration_mm, report.max_penetration_mm);
  result_.max_penetration_before_mm = maxOrNaN(result_.max_penetration_before_mm, report.max_penetration_before_mm);
  result_.max_penetration_free_mm = maxOrNaN(result_.max_penetration_free_mm, report.max_penetration_free_mm);
  result_.contacts = maxOrNaN(result_.contacts, report.contacts);
  result_.max_penetration_watched_mm = maxOrNaN(result_.max_penetration_watched_mm, report.max_penetration_watched_mm);
  result_.contact_iterations += report.iterations;
  result_.probes_off_surface += report.probes_off_surface;
  result_.probes_reseated += report.probes_reseated;
  result_.collision_ms += msSince(start);
}

void RBFMuscle::carryProbes(const std::vector<Eigen::Isometry3d>& motion_M) {
  std::vector<DualQuaternion> dq;
  for (const Eigen::Isometry3d& m : motion_M) dq.push_back(toDualQuaternion(m));
  predictPoints(rest_probes_M_, probe_weights_, dq, carried_probes_M_);
}

void RBFMuscle::appendFrameGeometry(std::vector<FrameGeometry>& geometry) const {
  TriangleMesh surface = deformer_->extractSurface(surface_cell_mm.get());
  surface.vertices_mm.colwise() += frame_offset_mm_;
  geometry.push_back(FrameGeometry{getName(), std::move(surface.vertices_mm), std::move(surface.triangles), {}});
  if (!fibre_tracker_) return;
  const FibreFrame& frame = fibre_tracker_->getFrame();
  const RestFibres& rest = fibre_tracker_->getRest();
  Eigen::Matrix3Xd vertices = frame.points_mm.cols() > 0 ? frame.points_mm : rest.points_mm;
  vertices.colwise() += frame_offset_mm_;
  std::vector<std::vector<int>> polylines(static_cast<size_t>(rest.count));
  for (int i = 0; i < rest.count; ++i)
    for (int j = 0; j <= rest.segments; ++j) polylines[static_cast<size_t>(i)].push_back(i * (rest.segments + 1) + j);
  geometry.push_back(FrameGeometry{getName() + "_fibres", std::move(vertices), Eigen::Matrix3Xi(3, 0), std::move(polylines)});
}

}  // namespace rbfmuscle
