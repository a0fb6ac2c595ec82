// SPDX-License-Identifier: Apache-2.0
#include "pipeline/muscle_pipeline.h"

#include "dynamics/quadrature.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_distance.h"
#include "pipeline/contact_stage.h"
#include "pipeline/fibre_stage.h"
#include "pipeline/prediction_stage.h"
#include "pipeline/surface_projection.h"
#include "pipeline/volume_stage.h"
#include "rbf/neighbour_lists.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rbfmuscle {

namespace {

/// The figures of a slot's table.
std::vector<ReportField> describeSlot(int slot) {
  switch (slot) {
    case MusclePipeline::kPrediction: return describeTable(PredictionStage::kReport);
    case MusclePipeline::kDescent: return describeTable(DescentStage::kReport);
    case MusclePipeline::kContacts: return describeTable(ContactStage::kReport);
    case MusclePipeline::kVolume: return describeTable(VolumeStage::kReport);
    case MusclePipeline::kFibres: return describeTable(FibreStage::kReport);
    case MusclePipeline::kSurface: return describeTable(SurfaceStage::kReport);
  }
  return {};
}

/// Puts the extracted rest surface's vertices onto the rest muscle's surface by Newton steps. The
/// extraction interpolates linearly between grid nodes, so where the field bends within a cell
/// (the psoas's thin origin) a vertex starts up to about 1 field unit off, and from there the
/// tracked surface's projection can take another way to f = 0 at each frame: its vertices slid
/// by up to 13 mm at rest and stepped by 15 mm between two frames of the rotation.
void putOntoSurface(const ImplicitField& shape, const SurfaceSettings& settings, TriangleMesh& surface) {
  for (Eigen::Index v = 0; v < surface.vertices_mm.cols(); ++v) {
    Eigen::Vector3d p = surface.vertices_mm.col(v);
    projectByNewton(shape, shape.calcSample(p), p, settings);
    surface.vertices_mm.col(v) = p;
  }
}

/// Whether each rest point (M) lies within `reach_mm` of one of the origin's bones.
std::vector<bool> findPointsOnBones(const MuscleDefinition& definition, const Eigen::Matrix3Xd& points_mm,
                                    double reach_mm) {
  std::vector<bool> on(static_cast<size_t>(points_mm.cols()), false);
  for (int b : definition.origin_bones) {
    const MeshDistance& bone = definition.bones.at(static_cast<size_t>(b)).grid->getMeshDistance();
    const Eigen::Isometry3d X_BM = definition.rest_X_MB.at(static_cast<size_t>(b)).inverse();
    for (Eigen::Index j = 0; j < points_mm.cols(); ++j)
      if (bone.findSignedClosestPoint(X_BM * Eigen::Vector3d(points_mm.col(j))).signed_distance_mm < reach_mm)
        on[static_cast<size_t>(j)] = true;
  }
  return on;
}

}  // namespace

MusclePipeline::MusclePipeline(const MuscleDefinition& definition, const PipelineSettings& settings) {
  const GaussianField& fit = definition.rest_field;
  state_ = std::make_unique<MuscleState>(fit, settings.cutoff);
  const DeformedField rest = state_->field;
  std::vector<bool> free_mask(static_cast<size_t>(fit.getNumCentres()));
  for (int k = 0; k < fit.getNumCentres(); ++k) free_mask[static_cast<size_t>(k)] = !definition.attachments.isAttached(k);

  QuadratureSettings quadrature_settings;
  quadrature_settings.target_count = settings.quadrature_points;
  const Quadrature quadrature = makeQuadrature(fit, quadrature_settings);
  state_->quadrature_mm = quadrature.points_mm;
  state_->volume_changes = Eigen::VectorXd::Ones(quadrature.points_mm.cols());

  // Contacts at rest: the rest clearance enters the rest volume and the rest surface.
  std::unique_ptr<ContactStage> contacts;
  state_->clearance_mm = Eigen::VectorXd::Constant(quadrature.points_mm.cols(), std::numeric_limits<double>::infinity());
  if (!definition.bones.empty()) {
    Eigen::AlignedBox3d reach = quadrature.box_mm;
    reach.min().array() -= quadrature.cell_mm;
    reach.max().array() += quadrature.cell_mm;
    contacts = std::make_unique<ContactStage>(BoneClearance(definition.bones), reach);
    FrameInput rest_input;
    rest_input.X_MB = definition.rest_X_MB;
    rest_input.bone_motion_M.assign(2, Eigen::Isometry3d::Identity());
    contacts->run(*state_, rest_input);
    for (Eigen::Index j = 0; j < quadrature.points_mm.cols(); ++j)
      state_->clearance_mm[j] = state_->bones->calcValue(quadrature.points_mm.col(j));
  }

  // Rest fibres and surface, then a lattice covering everything the map carries.
  RestFibres fibres;
  if (settings.fibres > 0) {
    FibreSettings fibre_settings;
    fibre_settings.count = settings.fibres;
    fibre_settings.segments = settings.fibre_segments;
    fibres = generateFibres(fit, definition.origin_area_M, definition.insertion_area_M, fibre_settings);
  }
  const MuscleShape rest_shape(*state_, nullptr, 0, BoneContact::kCut);  // as the tracked surface
  TriangleMesh rest_surface = extractIsoSurface(
      [&](const Eigen::Matrix3Xd& points, Eigen::VectorXd& values) {
        values.resize(points.cols());
        for (Eigen::Index j = 0; j < points.cols(); ++j) values[j] = rest_shape.calcValue(points.col(j));
      },
      quadrature.box_mm, settings.surface_cell_mm);
  putOntoSurface(rest_shape, settings.surface, rest_surface);
  const Eigen::Index n = fit.getNumCentres(), m = quadrature.points_mm.cols();
  Eigen::Matrix3Xd cover(3, n + m + fibres.points_mm.cols() + rest_surface.vertices_mm.cols());
  cover << fit.getCentres(), quadrature.points_mm, fibres.points_mm, rest_surface.vertices_mm;
  const MeshDistance muscle_surface(definition.rest_mesh_M, false);  // closest points only: sides by winding number
  // The map's smoothing spans the length it spans at the default resolution, whatever the
  // quadrature's (the cell scales as the cube root of the points).
  LatticeSettings lattice_settings = settings.lattice;
  lattice_settings.smoothing_cell_mm =
      quadrature.cell_mm * std::cbrt(static_cast<double>(settings.quadrature_points) / PipelineSettings{}.quadrature_points);
  lattice_ = std::make_shared<TissueLattice>(fit.getCentres(), definition.attachments, quadrature.box_mm.min(),
                                             quadrature.cell_mm, cover, &muscle_surface, state_->bones,
                                             lattice_settings);

  if (settings.lift_off && fibres.count > 0 && lattice_settings.joint_centre_mm)
    pulley_weight_ = lattice_->setLiftOffGuides(fibres.points_mm, fibres.segments + 1,
                                                findPointsOnBones(definition, fibres.points_mm, quadrature.cell_mm));

  NeighbourLists quadrature_lists = findMaterialNeighbours(rest, quadrature.points_mm);
  stages_.resize(kSlots);
  stages_[kPrediction] = std::make_unique<PredictionStage>(lattice_, fit.getCentres(), definition.attachments,
                                                           quadrature.points_mm, fit.getWeights());
  stages_[kDescent] = std::make_unique<DescentStage>(rest, quadrature.points_mm, quadrature.weights_mm3, free_mask,
                                                     settings.descent);
  stages_[kContacts] = std::move(contacts);
  auto volume = std::make_unique<VolumeStage>(*state_, std::move(quadrature_lists), free_mask,
                                              quadrature.weights_mm3[0], quadrature.cell_mm, settings.volume);
  rest_volume_mm3_ = volume->getRestVolume();
  stages_[kVolume] = std::move(volume);
  if (settings.fibres > 0) {
    auto fibre_stage = std::make_unique<FibreStage>(lattice_, std::move(fibres), rest, ProjectionSettings{});
    fibres_ = fibre_stage.get();
    state_->fibre_points_mm = fibres_->getRest().points_mm;
    state_->fibre_attachments_mm = fibres_->getRest().attachments_mm;
    stages_[kFibres] = std::move(fibre_stage);
  }
  auto surface = std::make_unique<SurfaceStage>(lattice_, std::move(rest_surface), rest, settings.surface);
  surface_ = surface.get();
  state_->surface_M = surface_->getRestSurface();
  stages_[kSurface] = std::move(surface);
  stage_ms_.assign(kSlots, std::numeric_limits<double>::quiet_NaN());
  for (int slot = 0; slot < kSlots; ++slot) slot_sizes_.push_back(describeSlot(slot).size());
}

const char* MusclePipeline::getSlotName(int slot) {
  static const char* const names[kSlots] = {"contacts", "prediction", "descent", "volume", "fibres", "surface"};
  return names[slot];
}


std::vector<ReportField> MusclePipeline::describeReports() {
  std::vector<ReportField> fields;
  for (int slot = 0; slot < kSlots; ++slot) {
    const std::vector<ReportField> table = describeSlot(slot);
    fields.insert(fields.end(), table.begin(), table.end());
  }
  for (int slot = 0; slot < kSlots; ++slot)
    fields.push_back({std::string(getSlotName(slot)) + "_ms", "ms",
                      std::string("wall time of the ") + getSlotName(slot) + " stage this frame (NaN when it did not run)"});
  fields.push_back({"update_ms", "ms", "wall time of the muscle's frame"});
  return fields;
}

void MusclePipeline::appendReports(std::vector<double>& values) const {
  for (int slot = 0; slot < kSlots; ++slot) {
    if (stages_[static_cast<size_t>(slot)] && !std::isnan(stage_ms_[static_cast<size_t>(slot)]))
      stages_[static_cast<size_t>(slot)]->appendReport(values);
    else
      values.insert(values.end(), slot_sizes_[static_cast<size_t>(slot)], std::numeric_limits<double>::quiet_NaN());
  }
  values.insert(values.end(), stage_ms_.begin(), stage_ms_.end());
  values.push_back(frame_ms_);
}

const Eigen::VectorXd& MusclePipeline::getFibreLengths() const {
  static const Eigen::VectorXd none;
  return fibres_ ? fibres_->getLengths() : none;
}

void MusclePipeline::run(const FrameInput& input) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  for (size_t i = 0; i < stages_.size(); ++i) {
    stage_ms_[i] = std::numeric_limits<double>::quiet_NaN();
    if (!stages_[i] || !stages_[i]->isNeeded(input)) continue;
    const Clock::time_point t = Clock::now();
    stages_[i]->run(*state_, input);
    stage_ms_[i] = std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  }
  frame_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

const RestFibres* MusclePipeline::getRestFibres() const { return fibres_ ? &fibres_->getRest() : nullptr; }

const TriangleMesh& MusclePipeline::getRestSurface() const { return surface_->getRestSurface(); }

}  // namespace rbfmuscle
