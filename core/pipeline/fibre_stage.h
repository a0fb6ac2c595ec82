// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Stage 5: the fibres carried with the tissue and kept inside the muscle.
#include "dynamics/tissue_lattice.h"
#include "fibres/fibre_generator.h"
#include "pipeline/frame_stage.h"
#include "rbf/neighbour_lists.h"

#include <memory>

namespace rbfmuscle {

/// Carries the rest fibres by the tissue map (their ends and their attachments on the areas
/// rigid with the origin and insertion bones; the tendons between count in the lengths).
/// Where the muscle is stretched, its fibres are taut: each interior point inside the muscle
/// moves towards its place in the taut map (tissue_lattice.h, step 4, the chords between the
/// bones instead of arcs about their joint) until it would leave the muscle min(f, s), so a
/// taut fibre straightens within the muscle and lies on a bone it meets. Then every point below
/// the margin is pushed back inside by a monotone ascent (fibre_projection.h): where the muscle
/// lies on a bone, a fibre point the map carried into the bone comes out along the bone's
/// surface, so the fibres slide over the bone rather than follow the map into it. An interior
/// point the ascent leaves outside climbs on by a pattern search, else is placed between the
/// nearest inside points of its fibre. Where the muscle is shortened, a fibre the map carries
/// round the joint sags below its string, the taut line over the joint (joint_lift_off.h), more
/// than it did at rest: each interior point rises away from the joint's axis by the difference,
/// spread over the lattice as the tissue's rises are and scaled by the lift fraction
/// (tissue_lattice.h, step 5), as far as the muscle allows. Reports the lengths.
class FibreStage final : public FrameStage {
 public:
  /// @param rest the rest fibres (M, mm)  @param rest_field the rest field (point lists)
  FibreStage(std::shared_ptr<TissueLattice> lattice, RestFibres rest, const DeformedField& rest_field,
             const ProjectionSettings& projection);

  /// What a frame's fibres did.
  struct Report {
    double mean_mm = kNaN, min_mm = kNaN, max_mm = kNaN, ratio = kNaN;
    double projected = kNaN, outside = kNaN, end_offset_max_mm = kNaN;
    double taut_fraction = kNaN, taut_move_max_mm = kNaN, lift_move_max_mm = kNaN;
  };
  static constexpr ReportEntry<Report> kReport[] = {
      {"fibre_length_mean_mm", "mm", "mean fibre length", &Report::mean_mm},
      {"fibre_length_min_mm", "mm", "shortest fibre", &Report::min_mm},
      {"fibre_length_max_mm", "mm", "longest fibre", &Report::max_mm},
      {"fibre_length_ratio", "1", "mean fibre length / rest mean", &Report::ratio},
      {"fibre_points_projected", "1", "fibre points pushed back inside the muscle this frame", &Report::projected},
      {"fibre_points_outside", "1", "fibre points still outside the muscle (min(f, s) ≤ 0) after the push",
       &Report::outside},
      {"fibre_end_offset_max_mm", "mm", "largest move of a fibre end off its place on its bone",
       &Report::end_offset_max_mm},
      {"fibre_taut_fraction", "1", "how far the fibres go from the blend's arcs to its chords (0: a muscle not stretched)",
       &Report::taut_fraction},
      {"fibre_taut_move_max_mm", "mm", "largest move of a fibre point towards its chord", &Report::taut_move_max_mm},
      {"fibre_lift_move_max_mm", "mm", "largest move of a fibre point of a shortened muscle back out towards its string",
       &Report::lift_move_max_mm},
  };

  void run(MuscleState& state, const FrameInput& input) override;
  void appendReport(std::vector<double>& values) const override { appendTable(kReport, report_, values); }
  /// Length of each fibre in the last run (rest lengths before the first) (mm).
  const Eigen::VectorXd& getLengths() const { return lengths_mm_; }
  /// The rest fibres.
  const RestFibres& getRest() const { return rest_; }

 private:
  std::shared_ptr<TissueLattice> lattice_;
  RestFibres rest_;
  ProjectionSettings projection_;
  LatticeBinding binding_;
  LatticeBinding attachment_binding_;  ///< the attachments, tied to bone 0 (origin) and 1 (insertion)
  NeighbourLists lists_;
  double rest_mean_mm_ = 0.0;
  static constexpr long kBlock = 64;  ///< fibre points per shared block (parallel_blocks.h)
  /// Step 3 (fibre_stage.cpp): moves the interior fibre points out towards their strings
  /// within `muscle`; returns the largest move (mm).
  double liftOff(MuscleState& state, const FrameInput& input, const ImplicitField& muscle);
  /// Moves each interior fibre point towards its target (3×P, mm) as far as `muscle` allows
  /// (advanceInside), the ends staying; returns the largest move (mm).
  double advanceInteriorPoints(const ImplicitField& muscle, const Eigen::Matrix3Xd& targets_mm, Eigen::Matrix3Xd& points);

  Eigen::Matrix3Xd taut_mm_;
  Eigen::VectorXd values_, lengths_mm_;
  Eigen::VectorXd moves_mm_;  ///< per point: a move towards a target, or an end's projection move (mm)
  Eigen::VectorXi steps_;     ///< per point: the projection's ascent steps
  Report report_;
};

}  // namespace rbfmuscle
