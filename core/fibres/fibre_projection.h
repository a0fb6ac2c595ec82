// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Moving a point back inside a muscle field, and fibre lengths.
///
/// Why a monotone ascent: a plain Newton iteration on f = a (the aim, just above the margin)
/// keeps every step, also one that lowers f. Its step (a − f) ∇f/‖∇f‖² grows as ∇f → 0 and is cut to
/// max_step_mm, so
///  - near a local maximum of f outside the muscle it overshoots back and forth;
///  - in a part thinner than one step (max f < a) it jumps from the ridge across
///    the part to the far side, f ≤ 0 again, and can stop there (unit test);
///  - far outside (f at its offset, ∇f = 0) it cannot move at all.
/// projectInside therefore only accepts steps that raise f (the Newton step, halved
/// until f rises), so the point ends at the highest f met on its path: f > 0 whenever the
/// path reaches the muscle, even where the muscle is thinner than the aim. Points the
/// ascent leaves outside climb on by climbByPatternSearch; those it cannot bring inside
/// either (no slope, or too far) are placed from their fibre neighbours by
/// placeBetweenInsideNeighbours.
#include "rbf/implicit_field.h"

#include <Eigen/Core>

#include <limits>

namespace rbfmuscle {

/// How points are pushed inside {f ≥ margin}.
struct ProjectionSettings {
  /// A point is inside enough when f ≥ margin (field unit ≈ mm of depth, the fit's
  /// clamped signed distance); > 0. The Newton steps aim just above it, at f = 1.02·margin:
  /// a point that falls just below the margin then moves by as little, so fibre lengths
  /// change continuously with the pose (aiming at 2·margin moved such a point half a
  /// margin at once, and made the moment arms of the iliacus and psoas twice as rough).
  double margin_mm = 0.5;
  /// Largest move of one step (mm), > 0: bounds the Newton step where ∇f is small; also the
  /// largest spacing of advanceInside's samples.
  double max_step_mm = 1.0;
  /// Accepted-step cap per point, ≥ 1 (the total move is ≤ max_steps · max_step_mm).
  int max_steps = 30;
  /// Halvings of a step that does not raise f before the point is taken as a local
  /// maximum of f along ∇f, ≥ 0 (the shortest step tried is max_step_mm / 2^max_halvings).
  int max_halvings = 10;
  /// Fibre ends are rigid with their bone; one that falls outside is still pushed in, but
  /// moves at most this far (mm, ≥ 0) from its bone-rigid place, within the 0.5 mm
  /// tolerance on end points after rounding (the fibre stage passes it as projectInside's
  /// max_move_mm).
  double end_max_move_mm = 0.499;
};

/// Why projectInside stopped.
enum class ProjectionStop {
  kWasInside,  ///< f ≥ margin at the start, nothing moved
  kReached,    ///< f ≥ margin after the steps
  kNoAscent,   ///< ‖∇f‖ < 1e-12, or no halving of the step raised f (local maximum of f)
  kStepCap,    ///< max_steps steps taken, f still < margin
  kMoveCap,    ///< the path reached max_move_mm, f still < margin
};

/// What projectInside did.
struct ProjectionResult {
  int steps = 0;                               ///< accepted steps
  double moved_mm = 0;                         ///< length of the path taken (mm)
  double value = 0;                            ///< f at the final point (the highest f met)
  ProjectionStop stop = ProjectionStop::kWasInside;  ///< why it stopped
};

/// Pushes p inside by a monotone ascent of f: while f(p) < margin, the Newton step on
/// f = a = 1.02·margin, δ = (a − f) ∇f / ‖∇f‖², shortened to max_step_mm, is halved
/// (at most max_halvings times) until f(p + δ) > f(p) and then taken. f never decreases,
/// so `p_mm` ends at the highest f on its path (f > 0 wherever the path reached the
/// muscle, also where the muscle is thinner than a). See the file comment for why.
/// The path is at most `max_move_mm` long (steps are shortened to what is left of it).
/// @throws std::invalid_argument on bad settings or a negative max_move_mm.
ProjectionResult projectInside(const ImplicitField& field, const ProjectionSettings& settings, Eigen::Vector3d& p_mm,
                               double max_move_mm = std::numeric_limits<double>::infinity());

/// Fallback for a fibre point p (f(p) ≤ 0 after projectInside) between the fibre points
/// a and b, both with f > 0, at the fraction t ∈ (0, 1) of the way from a to b (by point
/// index). q = a + t(b − a) on the chord; if f(q) ≤ 0, q walks in `samples` equal steps
/// towards the nearer of a, b (in t) and stops at the first sample with f ≥ margin, else
/// at the sample of highest f (never below f(nearer end) > 0). projectInside then
/// improves q (f only rises). Returns f at the placed point (> 0) and sets p_mm to it.
/// @throws std::invalid_argument if f(a) ≤ 0, f(b) ≤ 0, t ∉ (0, 1) or samples < 1.
double placeBetweenInsideNeighbours(const ImplicitField& field, const ProjectionSettings& settings,
                                    const Eigen::Vector3d& a_mm, const Eigen::Vector3d& b_mm, double t,
                                    Eigen::Vector3d& p_mm, int samples = 20);

/// Fallback for a point p that projectInside leaves outside (f(p) ≤ 0): the ascent stopped at
/// a local maximum of f along ∇f, a saddle between two parts of the muscle or where it is
/// thinner than the steps resolve. A pattern search climbs on: of the 26 points at the step
/// length from p (towards the faces, edges and corners of a cube), p moves to the highest if
/// it raises f, else the step halves; the step starts at max_step_mm, and the caps are the
/// ascent's (max_steps moves, max_halvings halvings). f only rises, so p climbs the nearest
/// slope: a point whose f falls just below 0 moves by about a step, not to another part of the
/// muscle. Once f > 0, projectInside goes on. Returns f at the final point; when the search
/// finds no f > 0, p is unchanged and the result is f(p) ≤ 0.
/// @throws std::invalid_argument on bad settings.
double climbByPatternSearch(const ImplicitField& field, const ProjectionSettings& settings, Eigen::Vector3d& p_mm);

/// The point of the segment from `from_mm` to `to_mm` just before the segment first leaves
/// {f ≥ level}, level = min(margin, f(from)): `to_mm` when it never does, `from_mm` when it
/// starts outside (f(from) ≤ 0) and leaves. A start just below the margin (a point the ascent
/// has just brought in) thus moves as one just above it does, instead of staying put. The
/// segment is sampled at most max_step_mm apart, and the first sample outside is bisected
/// against the last inside max_halvings times. Taking the first exit, not any inside sample
/// beyond, keeps the result continuous as the ends move (but where the segment grazes the
/// surface). f(from) is evaluated only once a sample falls below the margin, so a segment whose
/// samples all lie at or above the margin costs one evaluation per sample, and is taken whole
/// from any start.
/// @throws std::invalid_argument on bad settings.
Eigen::Vector3d advanceInside(const ImplicitField& field, const ProjectionSettings& settings,
                              const Eigen::Vector3d& from_mm, const Eigen::Vector3d& to_mm);

/// Checks the settings. @throws std::invalid_argument naming the bad value.
void checkProjectionSettings(const ProjectionSettings& settings);

/// Length of every fibre: fibre i is the polyline of columns i·(S+1) … i·(S+1)+S of
/// `points_mm` (3×N(S+1)); L_i = Σ_j ‖p_{j+1} − p_j‖ (mm). `out` is resized to N.
/// @throws std::invalid_argument if the column count is not a multiple of S+1 or S < 1.
void calcFibreLengths(const Eigen::Matrix3Xd& points_mm, int segments, Eigen::VectorXd& out);

/// The same with tendons: fibre i also runs from its origin attachment (column 2i of
/// `attachments_mm`, 3×2N) to its first point and from its last point to its insertion
/// attachment (column 2i+1), and those two distances count in L_i (mm).
/// @throws std::invalid_argument as above, or if `attachments_mm` has not 2N columns.
void calcFibreLengths(const Eigen::Matrix3Xd& points_mm, int segments, const Eigen::Matrix3Xd& attachments_mm,
                      Eigen::VectorXd& out);

}  // namespace rbfmuscle
