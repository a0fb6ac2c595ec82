// SPDX-License-Identifier: Apache-2.0
#include "pipeline/prediction_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

PredictionStage::PredictionStage(std::shared_ptr<TissueLattice> lattice, const Eigen::Matrix3Xd& rest_centres_mm,
                                 const Attachments& attachments, const Eigen::Matrix3Xd& quadrature_mm,
                                 const Eigen::VectorXd& rest_weights)
    : lattice_(std::move(lattice)), rest_weights_(rest_weights) {
  kernels_ = lattice_->bind(rest_centres_mm, attachments.bone_of_centre);
  quadrature_nodes_.resize(static_cast<size_t>(quadrature_mm.cols()));
  for (Eigen::Index j = 0; j < quadrature_mm.cols(); ++j) {
    const int node = lattice_->findNodeAt(quadrature_mm.col(j));
    if (node < 0)
      throw std::invalid_argument("PredictionStage: quadrature point " + std::to_string(j) + " is not a lattice node");
    quadrature_nodes_[static_cast<size_t>(j)] = node;
  }
}

void PredictionStage::run(MuscleState& state, const FrameInput& input) {
  lattice_->update(input.bone_motion_M);
  lattice_->carry(kernels_, centres_mm_, frames_);
  state.field.setWeights(rest_weights_);
  state.field.setKernels(centres_mm_, frames_);
  state.anchors_mm = centres_mm_;
  const Eigen::Matrix3Xd& nodes = lattice_->getNodes();
  lattice_->calcVolumeChanges(node_volume_changes_);
  const size_t m = quadrature_nodes_.size();
  state.quadrature_mm.resize(3, static_cast<Eigen::Index>(m));
  state.volume_changes.resize(static_cast<Eigen::Index>(m));
  for (size_t j = 0; j < m; ++j) {
    state.quadrature_mm.col(static_cast<Eigen::Index>(j)) = nodes.col(quadrature_nodes_[j]);
    state.volume_changes[static_cast<Eigen::Index>(j)] = node_volume_changes_[quadrature_nodes_[j]];
  }
  state.clearance_mm.setConstant(static_cast<Eigen::Index>(m), std::numeric_limits<double>::infinity());
  double overlap = 0.0;
  if (state.bones)
    for (Eigen::Index j = 0; j < static_cast<Eigen::Index>(m); ++j) {
      state.clearance_mm[j] = state.bones->calcValue(state.quadrature_mm.col(j));
      overlap = std::max(overlap, -state.clearance_mm[j]);
    }
  const Eigen::VectorXd& blend = lattice_->getBlendVolumeChanges();
  report_ = Report{static_cast<double>(state.field.countClampedFrames()), blend.minCoeff(), blend.maxCoeff(),
                   state.bones ? overlap : kNaN, lattice_->getLiftFraction(), lattice_->getLiftMax()};
}

}  // namespace rbfmuscle
