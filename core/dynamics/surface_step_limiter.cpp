#include "dynamics/surface_step_limiter.h"

#include "dynamics/field_surface.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_measures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace rbfmuscle {

namespace {

constexpr int kLatticeBits = 20;                          ///< bits per lattice index in an edge key
constexpr std::int64_t kLatticeOffset = 1 << (kLatticeBits - 1);  ///< indices in [−2¹⁹, 2¹⁹): ±1 km at 2 mm
constexpr std::uint64_t kLatticeMask = (std::uint64_t(1) << kLatticeBits) - 1;

/// Turns extractIsoSurface's per-grid edge keys into keys on the lattice cell·ℤ³ of M, the same
/// for every box on that lattice: (I, J, K) of the lower node, 20 bits each, then the 3-bit direction.
void toLatticeKeys(const Eigen::AlignedBox3d& box_mm, double cell_mm, std::vector<std::uint64_t>& keys) {
  const std::array<std::int64_t, 3> n = countIsoSurfaceNodes(box_mm, cell_mm);
  std::array<std::int64_t, 3> first;
  for (int a = 0; a < 3; ++a) first[static_cast<size_t>(a)] = std::llround(box_mm.min()(a) / cell_mm) + kLatticeOffset;
  for (std::uint64_t& key : keys) {
    const std::int64_t id = static_cast<std::int64_t>(key / 8), direction = static_cast<std::int64_t>(key % 8);
    const std::int64_t ijk[3] = {id % n[0], (id / n[0]) % n[1], id / (n[0] * n[1])};
    std::uint64_t packed = 0;
    for (int a = 0; a < 3; ++a)
      packed = (packed << kLatticeBits) | (static_cast<std::uint64_t>(ijk[a] + first[static_cast<size_t>(a)]) & kLatticeMask);
    key = packed * 8 + static_cast<std::uint64_t>(direction);
  }
}

/// The two nodes (M, mm) of the lattice edge `key` (toLatticeKeys).
std::pair<Eigen::Vector3d, Eigen::Vector3d> latticeEdgeNodes(std::uint64_t key, double cell_mm) {
  const std::uint64_t direction = key % 8, packed = key / 8;
  Eigen::Vector3d low;
  for (int a = 0; a < 3; ++a)
    low(a) = cell_mm * double(std::int64_t((packed >> (kLatticeBits * (2 - a))) & kLatticeMask) - kLatticeOffset);
  const Eigen::Vector3d step(double(direction & 1), double((direction >> 1) & 1), double((direction >> 2) & 1));
  return {low, low + cell_mm * step};
}

/// The bones' largest move at y (mm).
double calcBoneMove(const std::vector<Eigen::Isometry3d>& bone_steps_M, const Eigen::Vector3d& y) {
  double move_mm = 0.0;
  for (const Eigen::Isometry3d& step : bone_steps_M) move_mm = std::max(move_mm, (step * y - y).norm());
  return move_mm;
}

}  // namespace

std::string toString(StepLimitStop stop) {
  switch (stop) {
    case StepLimitStop::kWithinLimit: return "within_limit";
    case StepLimitStop::kScaled: return "scaled";
    case StepLimitStop::kHeld: return "held";
    case StepLimitStop::kPulledBack: return "pulled_back";
    case StepLimitStop::kOverLimit: return "over_limit";
    case StepLimitStop::kDisabled: return "disabled";
  }
  return "unknown";
}

SurfaceStepLimiter::SurfaceStepLimiter(const StepLimitSettings& settings, WeightEditLimits limits)
    : settings_(settings), limits_(std::move(limits)) {
  if (!(settings.cell_mm > 0.0) || !std::isfinite(settings.cell_mm)) {
    throw std::invalid_argument("StepLimitSettings::cell_mm " + std::to_string(settings.cell_mm) + ", expected > 0");
  }
  if (settings.max_trials < 1) {
    throw std::invalid_argument("StepLimitSettings::max_trials " + std::to_string(settings.max_trials) + ", expected >= 1");
  }
  if (settings.max_pull_rounds < 0) {
    throw std::invalid_argument("StepLimitSettings::max_pull_rounds " + std::to_string(settings.max_pull_rounds) +
                                ", expected >= 0");
  }
  if (std::isnan(settings.max_step_mm)) throw std::invalid_argument("StepLimitSettings::max_step_mm is NaN");
  if (limits_.max_abs_weights.size() != static_cast<Eigen::Index>(limits_.free_mask.size())) {
    throw std::invalid_argument("SurfaceStepLimiter: " + std::to_string(limits_.max_abs_weights.size()) +
                                " weight limits for " + std::to_string(limits_.free_mask.size()) + " centres");
  }
}

void SurfaceStepLimiter::checkField(const GaussianField& field, const char* where) const {
  if (field.getNumCentres() != static_cast<int>(limits_.free_mask.size())) {
    throw std::invalid_argument(std::string("SurfaceStepLimiter::") + where + ": the field has " +
                                std::to_string(field.getNumCentres()) + " centres, the limits " +
                                std::to_string(limits_.free_mask.size()));
  }
}

void SurfaceStepLimiter::setPreviousSurface(const GaussianField& field, const Eigen::AlignedBox3d& box_mm) {
  last_.mesh = extractFieldSurface(field, box_mm, settings_.cell_mm, &last_.edges);
  toLatticeKeys(box_mm, settings_.cell_mm, last_.edges);
  last_.field = field;
  adoptLastSurface();
}

void SurfaceStepLimiter::adoptLastSurface() {
  previous_.reset();
  previous_tree_.reset();
  if (last_.mesh.countTriangles() > 0) {
    previous_.emplace(std::move(last_));
    Surface& p = *previous_;
    p.by_edge.resize(p.edges.size());
    for (size_t v = 0; v < p.edges.size(); ++v) p.by_edge[v] = {p.edges[v], static_cast<int>(v)};
    std::sort(p.by_edge.begin(), p.by_edge.end());
  }
  last_ = Surface();  // not {}: GaussianField's default constructor is explicit
}

double SurfaceStepLimiter::measure(const GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                                   const std::vector<Eigen::Isometry3d>& bone_steps_M, double cap_mm, Surface& out,
                                   std::vector<std::pair<double, int>>* over) const {
  out.mesh = extractFieldSurface(field, box_mm, settings_.cell_mm, &out.edges);
  toLatticeKeys(box_mm, settings_.cell_mm, out.edges);
  if (over) over->clear();
  if (!previous_) return 0.0;
  const int n = out.mesh.countVertices();
  // A vertex whose edge the previous surface crossed too is within dist ≤ ‖y − y_prev‖ of it.
  std::vector<double> allowed(static_cast<size_t>(n));
  std::vector<char> unresolved(static_cast<size_t>(n), 0);
  bool any = false;
#pragma omp parallel for schedule(static) reduction(|| : any)
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector3d y = out.mesh.vertices_mm.col(v);
    allowed[static_cast<size_t>(v)] = calcBoneMove(bone_steps_M, y) + settings_.max_step_mm;
    const auto& by_edge = previous_->by_edge;
    const auto found = std::lower_bound(by_edge.begin(), by_edge.end(), std::make_pair(out.edges[static_cast<size_t>(v)], 0));
    if (found != by_edge.end() && found->first == out.edges[static_cast<size_t>(v)] &&
        (y - previous_->mesh.vertices_mm.col(found->second)).norm() <= allowed[static_cast<size_t>(v)])
      continue;
    unresolved[static_cast<size_t>(v)] = 1;
    any = true;
  }
  if (!any) return 0.0;
  if (!previous_tree_) previous_tree_.emplace(previous_->mesh, false);
  std::vector<double> excess(static_cast<size_t>(n), 0.0);
  double worst = 0.0;
#pragma omp parallel for schedule(dynamic, 64) reduction(max : worst)
  for (int v = 0; v < n; ++v) {
    if (!unresolved[static_cast<size_t>(v)]) continue;
    const Eigen::Vector3d y = out.mesh.vertices_mm.col(v);
    const double a = allowed[static_cast<size_t>(v)];
    // Most points are within their allowance: a search pruned to it is cheap.
    if (previous_tree_->calcUnsignedDistanceWithin(y, a) <= a) continue;
    const double e = std::min(previous_tree_->calcUnsignedDistanceWithin(y, a + cap_mm) - a, cap_mm);
    excess[static_cast<size_t>(v)] = e;
    worst = std::max(worst, e);
  }
  if (over)
    for (int v = 0; v < n; ++v)
      if (excess[static_cast<size_t>(v)] > 0.0) over->push_back({excess[static_cast<size_t>(v)], v});
  return worst;
}

void SurfaceStepLimiter::pullPointsBack(GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                                        const std::vector<Eigen::Isometry3d>& bone_steps_M, double cap_mm,
                                        StepLimitReport& report) {
  // One edit per neighbourhood and round: an edit moves f over the width of the Gaussians around
  // it (a few mm on the hip muscles), so closer edits would add up and overshoot.
  constexpr double kEditSpacing_mm = 4.0;
  const double cell = settings_.cell_mm, spacing = std::max(2.0 * cell, kEditSpacing_mm), min_spacing2 = spacing * spacing;
  double best = report.excess_mm;
  Eigen::VectorXd best_weights = field.getWeights();
  best_ = last_;
  double gain = 1.0;
  Eigen::VectorXd weights = field.getWeights();
  for (int round = 1; round <= settings_.max_pull_rounds && !over_.empty(); ++round) {
    report.pull_rounds = round;
    // Worst first.
    std::sort(over_.begin(), over_.end(),
              [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
    picked_.clear();
    for (const auto& [excess, v] : over_) {
      const Eigen::Vector3d y = last_.mesh.vertices_mm.col(v);
      if (std::any_of(picked_.begin(), picked_.end(), [&](const Eigen::Vector3d& p) { return (p - y).squaredNorm() < min_spacing2; }))
        continue;
      picked_.push_back(y);
      const double side = previous_->field.calcValue(y) > 0.0 ? 1.0 : -1.0;  // +1: sank into the previous muscle
      const auto [a, b] = latticeEdgeNodes(last_.edges[static_cast<size_t>(v)], cell);
      const FieldEvaluation at_a = field.calcEvaluation(a), at_b = field.calcEvaluation(b);
      const bool use_a = side > 0.0 ? at_a.value <= at_b.value : at_a.value > at_b.value;
      const FieldEvaluation& e = use_a ? at_a : at_b;
      const double target =
          side * gain * std::min(0.5, std::max(0.05, (excess + 0.5 * settings_.max_step_mm) * e.gradient.norm()));
      // Free centres only: the attached ones hold the muscle on its bones.
      if (changeValueAt(field, use_a ? a : b, target - e.value, limits_, weights, active_, false) > 0) {
        ++report.pull_edits;
        field.setWeights(weights);
      }
    }
    const double excess = measure(field, box_mm, bone_steps_M, cap_mm, last_, &over_);
    if (excess < best) {
      best = excess;
      best_weights = weights;
      best_ = last_;
    } else {
      gain *= 0.5;  // the edits overshot: smaller ones
    }
  }
  if (field.getWeights() != best_weights) field.setWeights(best_weights);
  std::swap(last_, best_);
  report.excess_mm = best;
}

StepLimitReport SurfaceStepLimiter::run(const GaussianField& start, GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                                        const std::vector<Eigen::Isometry3d>& bone_steps_M) {
  StepLimitReport report;
  if (!(settings_.max_step_mm > 0.0)) return report;
  checkField(field, "run");
  if (start.getNumCentres() != field.getNumCentres() || start.getShapes() != field.getShapes() ||
      start.getOffset() != field.getOffset() || start.getCutoff() != field.getCutoff()) {
    throw std::invalid_argument("SurfaceStepLimiter::run: the start and end fields differ in more than centres and weights");
  }
  if (box_mm.isEmpty()) throw std::invalid_argument("SurfaceStepLimiter::run: empty box");
  const double cap = 4.0 * settings_.max_step_mm;
  report.full_excess_mm = report.excess_mm = measure(field, box_mm, bone_steps_M, cap, last_);
  last_.field = field;
  if (!previous_) return report;  // nothing to compare with: disabled
  report.stop_reason = StepLimitStop::kWithinLimit;
  if (report.full_excess_mm <= 0.0) return report;

  const Eigen::Matrix3Xd end_centres = field.getCentres();
  const Eigen::VectorXd end_weights = field.getWeights();
  const int end_pieces = countComponents(last_.mesh);
  const auto setScale = [&](double t) {
    field.setCentrePositions(start.getCentres() + t * (end_centres - start.getCentres()));
    field.setWeights(start.getWeights() + t * (end_weights - start.getWeights()));
  };
  // The start first, then bisection for the largest t within the limit. While no t is within
  // it, the one of least excess is kept (the start can be worse than the end).
  double low = 0.0, high = 1.0, chosen = 1.0;
  bool within = false;
  const auto tryScale = [&](double t) {
    setScale(t);
    const double excess = measure(field, box_mm, bone_steps_M, cap, trial_);
    const bool ok = excess <= 0.0 && countComponents(trial_.mesh) <= end_pieces;
    if ((ok && (!within || t > chosen)) || (!ok && !within && excess < report.excess_mm)) {
      chosen = t;
      report.excess_mm = excess;
      std::swap(last_, trial_);
    }
    within = within || ok;
    return ok;
  };
  tryScale(0.0);
  for (report.trials = 1; report.trials < settings_.max_trials; ++report.trials) {
    const double t = 0.5 * (low + high);
    (tryScale(t) ? low : high) = t;
  }
  setScale(chosen);
  report.scale = chosen;
  report.stop_reason = chosen > 0.0 ? StepLimitStop::kScaled : StepLimitStop::kHeld;
  if (report.excess_mm > 0.0) {
    report.excess_mm = measure(field, box_mm, bone_steps_M, cap, last_, &over_);
    pullPointsBack(field, box_mm, bone_steps_M, cap, report);
    report.stop_reason = report.excess_mm > 0.0 ? StepLimitStop::kOverLimit : StepLimitStop::kPulledBack;
  }
  last_.field = field;
  return report;
}

StepLimitReport SurfaceStepLimiter::pullBack(GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                                             const std::vector<Eigen::Isometry3d>& bone_steps_M) {
  StepLimitReport report;
  if (!(settings_.max_step_mm > 0.0)) return report;
  checkField(field, "pullBack");
  if (box_mm.isEmpty()) throw std::invalid_argument("SurfaceStepLimiter::pullBack: empty box");
  const double cap = 4.0 * settings_.max_step_mm;
  report.full_excess_mm = report.excess_mm = measure(field, box_mm, bone_steps_M, cap, last_, &over_);
  if (previous_) {
    report.stop_reason = StepLimitStop::kWithinLimit;
    if (report.excess_mm > 0.0) {
      pullPointsBack(field, box_mm, bone_steps_M, cap, report);
      report.stop_reason = report.excess_mm > 0.0 ? StepLimitStop::kOverLimit : StepLimitStop::kPulledBack;
    }
  }
  last_.field = field;
  return report;
}

}  // namespace rbfmuscle
