// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Fibres of a muscle at rest: N polylines of S segments from the origin
/// attachment to the insertion attachment through the volume {f > 0}.
///
/// Method (deterministic, all in M, mm):
///  1. the inside {f ≥ margin} is sampled on a regular grid (interior_grid.h), and the fibres
///     run through the largest piece of it that reaches both areas (within r of the whole
///     inside's nearest node to each). Where a part of the muscle (a tendon) is thinner than
///     the grid's spacing, the grid splits the inside there, so it is refined (twice the
///     nodes, at most kMaxGridRefinements times) until one piece reaches both areas;
///  2. start candidates are the interior nodes within r of an origin region point
///     (r = attachment_radius_mm, grown ×1.5 only while there is none, cap 8: ends far
///     from their area move rigidly with its bone where the tissue does not);
///     among them, only the nodes with f ≥ end_depth when there are ≥ N such nodes, else
///     the N deepest (why: the fibre ends move rigidly with their bones while the surface
///     near the attachment deforms, so ends picked at the surface fall outside it, and they
///     may move at most end_max_move_mm off their attachment; docs/design.md, Fibres);
///     N start points are chosen by farthest-point sampling (first: the candidate
///     nearest the first region point), so they spread evenly over the attachment area;
///     with fewer candidates than N the fibres share them, converging as on a tendon;
///     each then climbs towards f = end_depth by a monotone ascent of at most half the grid
///     spacing (the grid samples the depth coarsely, 1.7 mm apart on a tendon about twice
///     as thick); the same for the end points at the insertion;
///  3. pairing without crossings: with d the direction from the mean start to the mean
///     end, e₁ the principal direction of the starts in the plane ⟂ d and e₂ = d × e₁,
///     both sets get coordinates (u, v) along (e₁, e₂) about their own mean, divided by
///     their own standard deviations; each set is sorted by u, cut into ⌈√N⌉ strips, each
///     strip sorted by v, and the i-th start is paired with the i-th end (corresponding
///     positions across the two attachment areas, as in a parallel-fibred muscle);
///  4. each fibre starts as the shortest interior grid path between its two ends
///     (edges cost more near the surface, centre_preference), resampled to kShapeSegments
///     equal arc-length segments;
///  5. relaxation, smoothing_iterations rounds over every interior point p_ij (fibre i,
///     point j), from the previous round's positions: a Laplacian step ½(½(p₋ + p₊) − p),
///     plus a spreading push away from the same-index points of the other fibres,
///     σ·r₀/4 · Σ_k u_ik exp(−‖p_ij − p_kj‖²/(2r₀²)) (u the unit vector from p_kj, only
///     ‖·‖ < 3r₀, component along the fibre removed, push capped at r₀; r₀ = √(V/(π N ℓ)),
///     V the interior volume, ℓ the distance between the mean start and mean end), so the
///     fibres fill the cross-section instead of bundling along the shortest routes;
///     then projectInside (fibre_projection.h). End points stay where they climbed to;
///  6. each fibre's shape is resampled to S equal arc-length segments, its new interior
///     points projected inside. The shape does not depend on S: relaxed at S itself, the
///     grid path's zigzags stayed in fine fibres (20 rounds smooth over about 3 segments), and
///     the gluteus maximus's rest fibres were 19 % longer at S = 60 than at S = 15, its
///     fibre length ratio at 80° of flexion 1.29 against 1.43, and the iliacus's flexion
///     moment arm at 80° turned negative;
///  7. each fibre is attached to its areas: its tendons run from its first and last point to
///     the nearest point of the origin and the insertion region, so the fibre runs from area
///     to area. The ends above lie inside the muscle, a median 7–9 mm from their areas in the
///     hip scenes (the deepest nodes near an area, and the segmented muscles stop 1–10 mm
///     short of the measured areas); the tendons span that, move rigidly with their bones and
///     count in the fibre's length.
/// The dissected fibre directions are not used to route the fibres; they can be
/// compared with the result (see the tests).
#include "fibres/fibre_projection.h"
#include "fibres/interior_grid.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

namespace rbfmuscle {

/// Most fibre points N·(S+1) allowed: 1e6. Every one is carried by the blend and projected
/// inside every frame (fibre_tracker.h), at about a microsecond or more each: beyond, frames
/// take seconds. The hip scenes use 100 × 16.
inline constexpr double kMaxFibrePoints = 1e6;

/// Most point-pair evaluations of the spreading push allowed while generating the fibres
/// (estimateSpreadingPairs): 1e10, a minute or two on a 2-core machine (1e9 pairs take
/// about 13 s of CPU). The push
/// compares each interior point of a fibre's shape with the same point of every other fibre in
/// every round, so the cost grows as rounds·N²·(kShapeSegments−1): 100 fibres take 3e6, 10 000
/// would take 3e10 (several minutes) and are refused up front instead.
inline constexpr double kMaxSpreadingPairs = 1e10;

/// How many times generateFibres doubles the interior grid's nodes to join the two areas
/// (8× the nodes, half the spacing).
inline constexpr int kMaxGridRefinements = 3;

/// Segments at which a fibre's shape is routed and relaxed (file comment, steps 4–5) before it
/// is sampled at the requested S: the relaxation then smooths over a fixed part of the fibre
/// whatever S is.
inline constexpr int kShapeSegments = 15;

struct FibreSettings;
/// rounds·N²·(kShapeSegments−1): the point pairs the spreading push evaluates for these settings.
double estimateSpreadingPairs(const FibreSettings& settings);

/// Settings of generateFibres.
struct FibreSettings {
  int count = 100;                   ///< N fibres, ≥ 1
  int segments = 15;                 ///< S segments per fibre, ≥ 1 (the shape is made at kShapeSegments)
  double attachment_radius_mm = 10;  ///< r: start/end candidates within r of a region point (mm), > 0
  /// Fibre ends are nodes with f ≥ end_depth when r holds ≥ N of them, else the N deepest,
  /// and climb towards it (field unit ≈ mm of depth, see file comment step 2), finite;
  /// ≤ margin means any interior node, unmoved.
  double end_depth = 4.0;
  int grid_nodes = 20000;            ///< interior grid nodes, ≥ 8
  double centre_preference = 1.0;    ///< c ≥ 0 of findShortestPath
  int smoothing_iterations = 20;     ///< relaxation rounds (smoothing, spreading, projection), ≥ 0
  double spreading = 1.0;            ///< σ ≥ 0 of the spreading push (0: none)
  ProjectionSettings projection;     ///< margin (f ≥ margin) and steps of the projection
};

/// The fibres at rest and how well they fill the muscle.
struct RestFibres {
  int count = 0;             ///< N
  int segments = 0;          ///< S
  /// Fibre i, point j (j = 0 origin end … S insertion end) at column i·(S+1)+j (3×N(S+1), mm, M).
  Eigen::Matrix3Xd points_mm;
  /// Fibre i's origin attachment at column 2i, its insertion attachment at 2i+1: the region
  /// points nearest its first and last point (step 7; 3×2N, mm, M).
  Eigen::Matrix3Xd attachments_mm;
  Eigen::VectorXd lengths_mm;  ///< rest length of each fibre, tendons included (mm)
  double min_value = 0;        ///< min f over all fibre points (> 0 means all inside)
  int points_below_margin = 0; ///< fibre points with f < margin after the relaxation
  /// Coverage: r₀ = √(V / (π Σ Lᵢ)) is the radius each fibre would own if the fibres
  /// filled the volume V evenly (mm).
  double ideal_radius_mm = 0;
  double mean_distance_mm = 0;   ///< mean distance of interior grid nodes to the nearest fibre (mm)
  double covered_fraction = 0;   ///< fraction of interior grid nodes within 2 r₀ of a fibre
  double attachment_radius_origin_mm = 0;     ///< r used at the origin after growth (mm)
  double attachment_radius_insertion_mm = 0;  ///< r used at the insertion after growth (mm)
  double end_climb_max_mm = 0;                ///< the most an end may climb off its grid node: half the spacing (mm)
  double grid_spacing_mm = 0;  ///< spacing of the interior grid the fibres were routed on (mm)
  int grid_refinements = 0;    ///< times that grid was refined to join the areas (step 1)
};

/// Generates the fibres (see file comment).
/// @param origin_region_mm 3×K₀ points marking the origin attachment (M, mm; landmarks or
///   attached centres), K₀ ≥ 1; `insertion_region_mm` the same for the insertion.
/// @throws std::invalid_argument on bad settings (including more than kMaxFibrePoints points or
///   kMaxSpreadingPairs pair evaluations, checked before any work), empty or non-finite regions, or when no
///   interior node lies near a region; std::runtime_error when no piece of the inside reaches
///   both regions, even on the finest grid (step 1).
RestFibres generateFibres(const GaussianField& field, const Eigen::Matrix3Xd& origin_region_mm,
                          const Eigen::Matrix3Xd& insertion_region_mm, const FibreSettings& settings = {});

}  // namespace rbfmuscle
