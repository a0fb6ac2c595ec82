#pragma once
/// @file
/// Keeping a deformed muscle in one piece: small pieces of {f > 0} that came apart
/// from the body ("islands") and bubbles of {f ≤ 0} inside it ("cavities") are found
/// on a grid, lowered below zero and raised above it.
///
/// Why: the field is a sum of isotropic Gaussians of fixed shape. Where the motion
/// stretches the muscle (the gluteus maximus by a median 1.6× and at most 2× at 80°
/// flexion), neighbouring centres move apart, the sum between them drops, and a
/// thin part can pinch off a small piece of the body. A fixed-shape isotropic
/// Gaussian cannot stretch with the tissue, so this is a property of the
/// representation, not of the descent; the guard makes the outcome explicit and
/// bounded instead of leaving floating pieces in the output.
#include "dynamics/local_value_change.h"
#include "rbf/field_on_grid.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

namespace rbfmuscle {

/// Settings of the topology guard.
struct TopologySettings {
  bool enabled = true;     ///< false: never look
  /// Grid spacing of the check (mm, > 0). With the same box and spacing as
  /// MuscleDeformer::extractSurface, the guard sees exactly the surface that is output.
  double cell_mm = 2.0;
  int max_rounds = 10;     ///< rounds of changes, ≥ 1 (each followed by another look)
  /// The top of an island is lowered to −margin and the bottom of a cavity raised to
  /// +margin (field unit, mm for a signed-distance fit; ≥ 0), so the volume step that
  /// follows (which moves b by a few tenths at 80° flexion) does not bring them back:
  /// on the gluteus maximus at 10° steps, 0.05 left one island at 80°, 0.25 none.
  double margin = 0.25;
  /// Islands of at least this many nodes are pieces of muscle (at the 2 mm default,
  /// 8 nodes ≈ 64 mm³, e.g. an insertion pinched off the belly) and are joined back to
  /// the body; smaller ones are crumbs and are removed (or joined: crumb_join_level). ≥ 1.
  std::int64_t bridge_nodes = 8;
  /// A crumb beside the body (at most two outside nodes between them) across a shallow dip is
  /// joined instead: its gap nodes are raised to this level (field unit, ≥ 0; 0 = crumbs are
  /// always removed) when the largest of those changes of f is less than lowering its top to
  /// −margin. Why: on a thin sheet near zero (the iliacus's top, 43°–54° of flexion) a node just
  /// above zero beside the body is part of the sheet; lowering it by 0.45 sank the sheet by over
  /// 1 mm, where raising the dip of −0.03 beside it takes 0.08.
  double crumb_join_level = 0.05;
  /// Necks (field unit, mm for a signed-distance fit; ≥ 0, 0 = off): a piece of
  /// {f > neck_level} of at least bridge_nodes nodes, apart from the largest one while
  /// {f > 0} is one piece, hangs on a thinning neck; the neck's nodes below the level are
  /// raised to 1.5 × neck_level. Why: under the motion a neck thins by a few hundredths
  /// per 1° frame (the iliacus's top, 35°–50° flexion); a raise of a tenth or so every few
  /// frames replaces the cut and the bridge (a change of 0.3 or more at once) that made
  /// the surface jump by 3.3 mm. 0.1 and 0.35 were measured no better than 0.2.
  double neck_level = 0.2;
};

/// Why the guard stopped.
enum class TopologyStop {
  kOnePiece,      ///< {f > 0} on the grid is one piece (or empty) without cavities
  kRoundCap,      ///< defects left after max_rounds rounds of changes
  kStuck,         ///< no centre could change at any defect
  kDisabled,      ///< the guard is off
};

/// Name of a stop reason ("one_piece", "round_cap", "stuck", "disabled").
std::string toString(TopologyStop stop);

/// What the guard did.
struct TopologyReport {
  int islands_found = 0;     ///< pieces of {f > 0} besides the largest at the first look
  int cavities_found = 0;    ///< enclosed pieces of {f ≤ 0} (bubbles) at the first look
  int defects_left = 0;      ///< islands + cavities at the last look
  int rounds = 0;            ///< looks at the grid (changes + 1 when any)
  int islands_removed = 0;   ///< crumb removals made (over all rounds)
  int islands_bridged = 0;   ///< bridge steps made (over all rounds)
  int necks_raised = 0;      ///< necks raised (see TopologySettings::neck_level)
  int weights_changed = 0;   ///< weight changes made (0: the field is untouched)
  std::int64_t grid_nodes = 0;    ///< nodes of the grid
  TopologyStop stop_reason = TopologyStop::kDisabled;
};

/// Finds islands and cavities and removes them, changing nothing but weights (of free
/// centres where there are any).
///
/// Each round evaluates f on the nodes box.min() + cell·(i, j, k) (the grid of
/// extractIsoSurface, whose box-face nodes count as outside) by calcValuesOnGrid (or,
/// while the centres and the box stay, by adding only the change of the weights and the
/// offset since the last look: addCentresOnGrid), and
/// labels the pieces of inside nodes connected along the edges of its Kuhn tetrahedra
/// (offsets in {0, 1}³ \ {0} and their negatives: 14 neighbours), which are the pieces
/// the extracted surface bounds. Every piece but the largest is an island; every piece
/// of {f ≤ 0} not joined to the box faces is a cavity. Each defect gets changes of f at
/// nodes x* per round: a cavity is raised to +margin at its lowest node; an island smaller than
/// bridge_nodes (a crumb) is lowered to −margin at its highest node; a larger island
/// is a piece of muscle and is joined back: every node with f ≤ 0 on the segment
/// between the closest (island, body) pair of nodes is raised to +margin, in path order
/// (when no weight can raise them, the island is lowered as a crumb instead). A crumb beside the
/// body is joined the same way, to crumb_join_level, when that is the smaller change. The change is
/// made through the weights of the free centres active at x* (the attached ones only
/// when no free one is) by changeValueAt (local_value_change.h: the smallest change in
/// Σ Δλₖ²/|λₖ| that makes f(x*) change by Δf, clamped, no weight changing sign). Rounds repeat until no defect is left or the
/// cap. Once the surface is one piece, necks are looked at once per run (neck_level): the
/// thinnest nodes of the widest path (the path through {f > 0} whose smallest value is
/// largest) between a large piece of {f > neck_level} and the largest one are raised the
/// same way, and the rounds go on. Deterministic (defects in label order, centres ascending).
class TopologyGuard {
 public:
  /// @param free_mask size N, true for the free centres (changed first)
  /// @param max_abs_weights size N, ≥ 0: |λₖ| never goes above this (the deformer gives
  ///   2|λₖ⁰| + mean |λ⁰|, so repeated fills over many frames cannot grow a weight
  ///   without bound)
  /// @throws std::invalid_argument for bad settings (names the field) or limits.
  TopologyGuard(std::vector<bool> free_mask, Eigen::VectorXd max_abs_weights, const TopologySettings& settings);

  /// Checks `field` over the grid of `box_mm` and removes islands and cavities (see
  /// class comment).
  /// @throws std::invalid_argument if the mask size differs from N or the box is empty.
  TopologyReport run(GaussianField& field, const Eigen::AlignedBox3d& box_mm);

  /// Number of closed surfaces the extraction over `box_mm` would give (pieces of
  /// {f > 0} plus cavities), without changing the field.
  int countPieces(const GaussianField& field, const Eigen::AlignedBox3d& box_mm);

  /// The settings.
  const TopologySettings& getSettings() const { return settings_; }

 private:
  /// Changes f(x) by `change` through `weights` (see class comment); false if no weight
  /// changed (no centre active at x, or every one at its limit or zero).
  bool changeValueAt(const GaussianField& field, const Eigen::Vector3d& x_mm, double change, Eigen::VectorXd& weights,
                     TopologyReport& report);
  /// The nodes with f ≤ 0 on the segment joining the closest nodes of `island` and `body`, in path order.
  void findGapNodes(int island, int body, std::vector<std::int64_t>& gap);
  /// f at `node` with this round's weight changes (`weights` against the field's own).
  double valueWithChanges(const GaussianField& field, const Eigen::VectorXd& weights, std::int64_t node);
  /// f on the nodes of `grid` into value_of_node_: in full when the grid, the centres, the
  /// shapes or the cut-off differ from the last evaluation, else by adding the change of
  /// the weights and the offset (equal up to rounding).
  void updateValues(const GaussianField& field, const RegularGrid& grid);
  /// Evaluates the grid, labels the pieces of {f > level} and, at level 0 only, then the
  /// cavities (appended to piece_size_/piece_top_); returns the number of pieces of {f > level}.
  int label(const GaussianField& field, const Eigen::AlignedBox3d& box_mm, double level);
  /// Raises the thinnest nodes of necks (TopologySettings::neck_level); true if a weight changed.
  bool raiseNecks(const GaussianField& field, const Eigen::AlignedBox3d& box_mm, Eigen::VectorXd& weights,
                  TopologyReport& report);
  static constexpr double kNeckRaise = 1.5;  ///< a neck's nodes are raised to this × neck_level
  /// A crumb is beside the body when at most this many outside nodes lie between them.
  static constexpr size_t kCrumbGapNodes = 2;

  static constexpr int kOutside = -2;     ///< node state: on a box face, or f ≤ 0
  static constexpr int kUnlabelled = -1;  ///< node state: inside, no piece yet

  WeightEditLimits limits_;  ///< which weights the guard may change, and how far
  TopologySettings settings_;
  RegularGrid grid_;
  std::vector<double> value_of_node_;     ///< f per node
  std::vector<int> piece_of_node_;        ///< kOutside, kUnlabelled or the piece label, per node
  std::vector<std::int64_t> inside_ids_;  ///< nodes with f > 0 off the box faces, ascending
  std::vector<std::int64_t> piece_size_;
  std::vector<std::int64_t> piece_top_;  ///< highest node of each piece, lowest of each cavity
  std::vector<std::uint8_t> exterior_;   ///< 1: a node of {f ≤ 0} already reached (from the faces or a cavity)
  std::vector<std::int64_t> queue_;
  std::vector<std::int64_t> island_nodes_;  ///< nodes of the island being bridged
  std::vector<std::int64_t> gap_nodes_;     ///< outside nodes of the bridge being made
  std::vector<double> bottleneck_;          ///< widest-path width per node (raiseNecks)
  std::vector<std::int64_t> predecessor_;   ///< widest-path predecessor per node (raiseNecks)
  ActiveCentres active_;
  // The field of the last evaluation (updateValues).
  Eigen::Matrix3Xd evaluated_centres_mm_;
  Eigen::VectorXd evaluated_weights_;
  Eigen::VectorXd evaluated_shapes_;
  double evaluated_offset_ = 0.0;
  double evaluated_cutoff_ = 0.0;
  std::vector<int> changed_centres_;
  Eigen::VectorXd weight_change_;
};

}  // namespace rbfmuscle
