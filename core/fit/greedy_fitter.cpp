// SPDX-License-Identifier: Apache-2.0
#include "fit/greedy_fitter.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "io/format_number.h"
#include "rbf/spatial_grid.h"

namespace rbfmuscle {
namespace {

/// φ below this is ignored when scoring candidates (scores are a guide; the
/// exact weights come from the refit).
constexpr double kScoreCutoff = 1e-4;
/// After the last round: at most this many times, violated check points join and the
/// weights are refitted.
constexpr int kMaxFinalCheckPasses = 3;

/// The best shape for one candidate sample.
struct CandidateChoice {
  int sample = -1;
  double shape = 0.0;         ///< α (mm⁻²)
  double weight = 0.0;        ///< optimal single-Gaussian weight g/h
  double score = 0.0;         ///< g²/h: error reduction on the scoring subset
  double regularised = 1e300; ///< C_r of eq. 7.12 (lower is better)
};

double calcRms(const Eigen::VectorXd& values) {
  return values.size() ? std::sqrt(values.squaredNorm() / static_cast<double>(values.size())) : 0.0;
}

class GreedyFitter {
 public:
  GreedyFitter(const SampleSet& samples, const FitSettings& settings, FindNearCrumbsFn find_near_crumbs)
      : samples_(samples), settings_(settings), find_near_crumbs_(std::move(find_near_crumbs)),
        design_(samples.getNumSamples()),
        check_design_(samples.getNumCheckPoints()) {
    if (settings.max_centres < 1) throw std::invalid_argument("fit: max_centres must be ≥ 1");
    // Beyond these the targets' squares overflow (a clamp of 1e300 mm made every residual NaN).
    if (!(settings.clamp_mm > 0 && settings.clamp_mm <= FitSettings::kMaxClamp_mm))
      throw std::invalid_argument("fit: clamp " + io::formatNumber(settings.clamp_mm) + " mm, expected > 0 and ≤ " +
                                  io::formatNumber(FitSettings::kMaxClamp_mm) + " mm");
    if (!(settings.normal_offset_mm > 0 && settings.normal_offset_mm <= settings.clamp_mm))
      throw std::invalid_argument("fit: normal offset " + io::formatNumber(settings.normal_offset_mm) +
                                  " mm, expected > 0 and at most the clamp (" + io::formatNumber(settings.clamp_mm) +
                                  " mm): samples beyond the clamp carry no distance");
    if (!(settings.tolerance_mm >= 0 && std::isfinite(settings.tolerance_mm)))
      throw std::invalid_argument("fit: tolerance " + io::formatNumber(settings.tolerance_mm) +
                                  " mm, expected ≥ 0 (0: the centre budget alone)");
    shapes_ = settings.global_shape_per_mm2 > 0
                  ? std::vector<double>{settings.global_shape_per_mm2}
                  : settings.shapes_per_mm2;
    if (shapes_.empty()) throw std::invalid_argument("fit: the shape set is empty");
    for (double a : shapes_)
      if (!(a > 0) || !std::isfinite(a))
        throw std::invalid_argument("fit: shape " + io::formatNumber(a) + " mm^-2 is not > 0");
    alpha_max_ = *std::max_element(shapes_.begin(), shapes_.end());
    alpha_min_ = *std::min_element(shapes_.begin(), shapes_.end());
    offset_ = -settings.clamp_mm;
    y_ = (samples.target.array() - offset_).matrix();
    residual_ = y_;
    s_max_ = std::max(samples.signed_distance_mm.cwiseAbs().maxCoeff(), 1e-9);
    for (int i = 0; i < samples.getNumSamples(); ++i)
      if (samples.kinds[i] == SampleKind::kSurface) surface_rows_.push_back(i);

    sample_grid_.build(samples.points_mm, 4.0);
    check_added_.assign(static_cast<std::size_t>(samples.getNumCheckPoints()), 0);
    if (samples.getNumCheckPoints() > 0) check_grid_.build(samples.check_points_mm, 4.0);
  }

  GreedyFitResult run(const FitProgressFn& progress) {
    GreedyFitResult result;
    const double min_separation = 2.0 * settings_.normal_offset_mm;
    while (getNumCentres() < settings_.max_centres) {
      ++result.rounds;
      const int remaining = settings_.max_centres - getNumCentres();
      const int batch = std::min(
          remaining, std::max(1, static_cast<int>(std::ceil(settings_.batch_fraction * getNumCentres()))));
      const std::vector<int> candidates =
          pickCandidates(std::max(settings_.candidates_per_round, 3 * batch), min_separation);
      const std::vector<CandidateChoice> accepted = chooseCentres(candidates, batch);
      if (accepted.empty()) {
        result.stop_reason = "no candidate reduces the error";
        break;
      }
      for (const CandidateChoice& choice : accepted) addCentre(choice);
      refit(settings_.refit_iterations);
      if (getNumCentres() >= settings_.check_start_fraction * settings_.max_centres) {
        result.check_samples_added += addViolatedCheckPoints();
        result.near_crumb_samples_added += addNearCrumbs();
      }
      const FitProgress state = makeProgress(result.rounds);
      if (progress) progress(state);
      if (settings_.tolerance_mm > 0 && state.rms_surface_mm <= settings_.tolerance_mm) {
        result.stop_reason = "tolerance";
        break;
      }
    }
    if (result.stop_reason.empty()) result.stop_reason = "centre budget";
    if (getNumCentres() == 0)  // nothing to refit, and no surface
      throw std::invalid_argument("fit: no centre reduces the error of the samples; the fit options (clamp, shapes) "
                                  "do not suit this mesh");
    result.final_refit = refit(settings_.final_refit_iterations);
    bool settled = false;
    for (int pass = 0; pass < kMaxFinalCheckPasses && !settled; ++pass) {
      const int checks = addViolatedCheckPoints(), crumbs = addNearCrumbs();
      result.check_samples_added += checks;
      result.near_crumb_samples_added += crumbs;
      settled = checks == 0 && crumbs == 0;
      if (!settled) result.final_refit = refit(settings_.final_refit_iterations);
    }
    if (find_near_crumbs_ && !settled)
      result.near_crumbs_left = static_cast<int>(find_near_crumbs_(makeField()).points_mm.cols());
    const FitProgress final_state = makeProgress(result.rounds);
    result.rms_surface_mm = final_state.rms_surface_mm;
    result.rms_all_mm = final_state.rms_all_mm;
    result.field = makeField();
    return result;
  }

 private:
  int getNumCentres() const { return static_cast<int>(centre_shapes_.size()); }
  GaussianField makeField() const { return GaussianField(offset_, centres_, lambda_, centre_shapes_, settings_.cutoff); }

  /// Whether a centre at `sample` with a weight of sign `weight` obeys the
  /// sign rule: a centre inside the mesh may only add (λ > 0), one outside
  /// only carve (λ < 0). Surface vertices are no centres: a narrow Gaussian
  /// there makes a bubble that leaves the muscle as an island.
  bool isAllowedSign(int sample, double weight) const {
    const double s = samples_.signed_distance_mm[sample];
    return s != 0.0 && (s < 0) == (weight > 0);
  }

  /// Samples of largest |residual|, each at least `separation` from the others.
  std::vector<int> pickCandidates(int count, double separation) const {
    const int S = samples_.getNumSamples();
    std::vector<int> order(S);
    std::iota(order.begin(), order.end(), 0);
    const int pool = std::min(S, 40 * count);
    auto larger = [&](int a, int b) {
      const double ra = std::abs(residual_[a]), rb = std::abs(residual_[b]);
      return ra != rb ? ra > rb : a < b;
    };
    std::partial_sort(order.begin(), order.begin() + pool, order.end(), larger);
    std::vector<int> picked;
    const double separation2 = separation * separation;
    for (int n = 0; n < pool && static_cast<int>(picked.size()) < count; ++n) {
      if (!isAllowedSign(order[n], residual_[order[n]])) continue;
      const Eigen::Vector3d p = samples_.points_mm.col(order[n]);
      bool far = true;
      for (int q : picked)
        if ((samples_.points_mm.col(q) - p).squaredNorm() < separation2) {
          far = false;
          break;
        }
      if (far) picked.push_back(order[n]);
    }
    return picked;
  }

  /// Scores every candidate with every shape and returns up to `batch`
  /// non-overlapping choices, best regularised cost first.
  std::vector<CandidateChoice> chooseCentres(const std::vector<int>& candidates, int batch) const {
    const int C = static_cast<int>(candidates.size());
    const int A = static_cast<int>(shapes_.size());
    std::vector<CandidateChoice> scored(static_cast<std::size_t>(C) * A);
#pragma omp parallel
    {
      std::vector<int> near;
      std::vector<double> r2;
#pragma omp for schedule(dynamic, 1)
      for (int c = 0; c < C; ++c) scoreCandidate(candidates[c], near, r2, &scored[static_cast<std::size_t>(c) * A]);
    }
    double best_score = 0.0;
    for (const CandidateChoice& s : scored) best_score = std::max(best_score, s.score);
    if (!(best_score > 0)) return {};

    const double gamma = settings_.regularisation_gamma;
    std::vector<CandidateChoice> best_per_candidate;
    for (int c = 0; c < C; ++c) {
      CandidateChoice best;
      for (int a = 0; a < A; ++a) {
        CandidateChoice s = scored[static_cast<std::size_t>(c) * A + a];
        if (!(s.score > 0)) continue;
        const double distance = std::abs(samples_.signed_distance_mm[s.sample]);
        s.regularised = gamma * (1.0 - s.score / best_score) +
                        (1.0 - gamma) * (distance / s_max_) * (s.shape / alpha_max_);
        if (s.regularised < best.regularised) best = s;
      }
      if (best.sample >= 0) best_per_candidate.push_back(best);
    }
    std::stable_sort(best_per_candidate.begin(), best_per_candidate.end(),
                     [](const CandidateChoice& a, const CandidateChoice& b) { return a.regularised < b.regularised; });

    // Two new centres of one batch must not cover the same error: keep them
    // at least the narrower one's σ = α^−½ apart (the wider one's σ would let
    // a single wide centre block a whole batch).
    std::vector<CandidateChoice> accepted;
    for (const CandidateChoice& choice : best_per_candidate) {
      if (static_cast<int>(accepted.size()) >= batch) break;
      const Eigen::Vector3d p = samples_.points_mm.col(choice.sample);
      bool apart = true;
      for (const CandidateChoice& other : accepted) {
        const double sigma = 1.0 / std::sqrt(std::max(choice.shape, other.shape));
        if ((samples_.points_mm.col(other.sample) - p).norm() < sigma) {
          apart = false;
          break;
        }
      }
      if (apart) accepted.push_back(choice);
    }
    return accepted;
  }

  /// Fills out[a] with the single-Gaussian score of a centre at `sample` with
  /// shape a. A wide shape reaches many samples: past kScoreSamplesPerShape
  /// neighbours every k-th one (in index order) stands for k.
  void scoreCandidate(int sample, std::vector<int>& near, std::vector<double>& r2,
                      CandidateChoice* out) const {
    const Eigen::Vector3d centre = samples_.points_mm.col(sample);
    const double log_inv = std::log(1.0 / kScoreCutoff);
    sample_grid_.findWithinRadius(centre, std::sqrt(log_inv / alpha_min_), near);
    r2.resize(near.size());
    for (std::size_t n = 0; n < near.size(); ++n) r2[n] = (samples_.points_mm.col(near[n]) - centre).squaredNorm();
    for (std::size_t a = 0; a < shapes_.size(); ++a) {
      const double alpha = shapes_[a];
      const double r2_max = log_inv / alpha;
      long long reach = 0;
      for (double d2 : r2) reach += d2 <= r2_max;
      const long long stride = std::max<long long>(1, reach / settings_.score_samples);
      double g = 0.0, h = 0.0;
      long long seen = 0;
      for (std::size_t n = 0; n < near.size(); ++n) {
        if (r2[n] > r2_max || seen++ % stride != 0) continue;
        const double phi = std::exp(-alpha * r2[n]);
        g += phi * residual_[near[n]];
        h += phi * phi;
      }
      CandidateChoice& choice = out[a];
      choice.sample = sample;
      choice.shape = alpha;
      if (h <= 0) continue;
      choice.weight = g / h;
      // A centre of the wrong sign for its side only cancels its neighbours,
      // makes islands and roughens the curvature field.
      choice.score = isAllowedSign(sample, choice.weight) ? static_cast<double>(stride) * g * g / h : 0.0;
    }
  }

  void addCentre(const CandidateChoice& choice) {
    const Eigen::Vector3d centre = samples_.points_mm.col(choice.sample);
    const double radius = std::sqrt(std::log(1.0 / settings_.cutoff) / choice.shape);
    std::vector<int> rows;
    sample_grid_.findWithinRadius(centre, radius, rows);
    std::vector<double> values(rows.size());
    for (std::size_t n = 0; n < rows.size(); ++n)
      values[n] = std::exp(-choice.shape * (samples_.points_mm.col(rows[n]) - centre).squaredNorm());
    design_.appendColumn(std::move(rows), std::move(values));
    if (samples_.getNumCheckPoints() > 0) {
      std::vector<int> check_rows;
      check_grid_.findWithinRadius(centre, radius, check_rows);
      std::vector<double> check_values(check_rows.size());
      for (std::size_t n = 0; n < check_rows.size(); ++n)
        check_values[n] = std::exp(-choice.shape * (samples_.check_points_mm.col(check_rows[n]) - centre).squaredNorm());
      check_design_.appendColumn(std::move(check_rows), std::move(check_values));
    }
    const int k = getNumCentres();
    centres_.conservativeResize(3, k + 1);
    centres_.col(k) = centre;
    centre_shapes_.conservativeResize(k + 1);
    centre_shapes_[k] = choice.shape;
    lambda_.conservativeResize(k + 1);
    lambda_[k] = choice.weight;
  }

  /// Makes the check points at least the normal offset d from the surface (|t| ≥ d) where the
  /// field does not lie on their side by more than check_slope·|t| (at 0: where it is on the
  /// wrong side or at 0) samples: rows of the design, candidates for a centre and terms of the
  /// refit. At most candidates_per_round of them, largest |t − f| first. Returns how many.
  int addViolatedCheckPoints() {
    const int P = samples_.getNumCheckPoints();
    if (P == 0) return 0;
    Eigen::VectorXd fitted;
    check_design_.multiply(lambda_, fitted);
    std::vector<int> violated;
    for (int i = 0; i < P; ++i) {
      if (check_added_[static_cast<std::size_t>(i)]) continue;
      const double t = samples_.check_target[i], f = offset_ + fitted[i];
      const double margin = settings_.check_slope * std::abs(t);
      if (std::abs(t) >= settings_.normal_offset_mm && (t > 0 ? f <= margin : f > -margin)) violated.push_back(i);
    }
    if (violated.empty()) return 0;
    // The worst first, and no more than a round examines as candidates: where the budget is
    // too small for the shape the field is wrong at most check points, and taking them all
    // would turn the fit into one of the band (a box with 80 centres: 1971 of 2000 taken, and
    // a cavity 26 mm deep came out).
    const std::size_t cap = static_cast<std::size_t>(std::max(1, settings_.candidates_per_round));
    if (violated.size() > cap) {
      auto worse = [&](int a, int b) {
        const double ea = std::abs(samples_.check_target[a] - offset_ - fitted[a]);
        const double eb = std::abs(samples_.check_target[b] - offset_ - fitted[b]);
        return ea != eb ? ea > eb : a < b;
      };
      std::partial_sort(violated.begin(), violated.begin() + static_cast<std::ptrdiff_t>(cap), violated.end(), worse);
      violated.resize(cap);
      std::sort(violated.begin(), violated.end());
    }
    Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(violated.size()));
    Eigen::VectorXd signed_distance(points.cols()), values(points.cols());
    for (Eigen::Index n = 0; n < points.cols(); ++n) {
      const int i = violated[static_cast<std::size_t>(n)];
      check_added_[static_cast<std::size_t>(i)] = 1;
      points.col(n) = samples_.check_points_mm.col(i);
      signed_distance[n] = samples_.check_signed_distance_mm[i];
      values[n] = fitted[i];
    }
    appendSamples(points, signed_distance, values, SampleKind::kCheck);
    return static_cast<int>(points.cols());
  }

  /// Makes the peaks and floors of the near crumbs of the current field (find_near_crumbs_) samples, at
  /// most candidates_per_round of them, the nearest f = 0 first. Returns how many.
  int addNearCrumbs() {
    if (!find_near_crumbs_) return 0;
    const GaussianField field = makeField();
    ExtraSamples found = find_near_crumbs_(field);
    const Eigen::Index add = std::min<Eigen::Index>(found.points_mm.cols(), std::max(1, settings_.candidates_per_round));
    if (add == 0) return 0;
    Eigen::VectorXd values(add);  // Σ λφ, as the design's rows hold it
    for (Eigen::Index n = 0; n < add; ++n) values[n] = field.calcValue(found.points_mm.col(n)) - offset_;
    appendSamples(found.points_mm.leftCols(add), found.signed_distance_mm.head(add), values, SampleKind::kNearCrumb);
    return static_cast<int>(add);
  }

  /// Appends samples at `points_mm` with signed distances s, where the field's Σ λφ is `fitted`:
  /// rows of the design, candidates for a centre and terms of every later refit.
  void appendSamples(const Eigen::Matrix3Xd& points_mm, const Eigen::VectorXd& signed_distance_mm,
                     const Eigen::VectorXd& fitted, SampleKind kind) {
    const Eigen::Index S = samples_.getNumSamples(), add = points_mm.cols();
    samples_.points_mm.conservativeResize(3, S + add);
    samples_.signed_distance_mm.conservativeResize(S + add);
    samples_.target.conservativeResize(S + add);
    samples_.target.tail(add) = calcTargets(signed_distance_mm, settings_.clamp_mm);
    y_.conservativeResize(S + add);
    residual_.conservativeResize(S + add);
    std::vector<int> cols;
    std::vector<double> values;
    for (Eigen::Index n = 0; n < add; ++n) {
      const Eigen::Vector3d p = points_mm.col(n);
      samples_.points_mm.col(S + n) = p;
      samples_.signed_distance_mm[S + n] = signed_distance_mm[n];
      samples_.kinds.push_back(kind);
      y_[S + n] = samples_.target[S + n] - offset_;
      residual_[S + n] = y_[S + n] - fitted[n];
      cols.clear();
      values.clear();
      for (int k = 0; k < getNumCentres(); ++k) {
        const double phi = std::exp(-centre_shapes_[k] * (p - centres_.col(k)).squaredNorm());
        if (phi >= settings_.cutoff) {
          cols.push_back(k);
          values.push_back(phi);
        }
      }
      design_.appendRow(cols, values);
    }
    sample_grid_.build(samples_.points_mm, 4.0);
  }

  RefitReport refit(int max_iterations) {
    const Eigen::VectorXd norms = design_.calcColumnNormsSquared();
    const double mu = settings_.ridge * norms.mean();
    const RefitReport report =
        refitWeights(design_, y_, mu, max_iterations, settings_.refit_tolerance, lambda_);
    Eigen::VectorXd fitted;
    design_.multiply(lambda_, fitted);
    residual_ = y_ - fitted;
    return report;
  }

  FitProgress makeProgress(int round) const {
    FitProgress state;
    state.round = round;
    state.centres = getNumCentres();
    state.max_centres = settings_.max_centres;
    Eigen::VectorXd surface(surface_rows_.size());
    for (std::size_t n = 0; n < surface_rows_.size(); ++n) surface[n] = residual_[surface_rows_[n]];
    state.rms_surface_mm = calcRms(surface);
    state.rms_all_mm = calcRms(residual_);
    return state;
  }

  SampleSet samples_;  ///< the fitting samples, joined by violated check points
  const FitSettings& settings_;
  FindNearCrumbsFn find_near_crumbs_;
  std::vector<double> shapes_;
  double alpha_max_ = 1.0;
  double alpha_min_ = 1.0;
  double offset_ = 0.0;
  double s_max_ = 1.0;
  Eigen::VectorXd y_;         ///< t − b at every sample
  Eigen::VectorXd residual_;  ///< t − f at every sample
  std::vector<int> surface_rows_;
  SpatialGrid sample_grid_;
  DesignMatrix design_;
  DesignMatrix check_design_;      ///< φ of every centre at every check point
  SpatialGrid check_grid_;
  std::vector<char> check_added_;  ///< per check point: already made a sample
  Eigen::Matrix3Xd centres_;
  Eigen::VectorXd centre_shapes_;
  Eigen::VectorXd lambda_;
};

}  // namespace

GreedyFitResult fitGreedy(const SampleSet& samples, const FitSettings& settings, const FitProgressFn& progress,
                          const FindNearCrumbsFn& find_near_crumbs) {
  return GreedyFitter(samples, settings, find_near_crumbs).run(progress);
}

}  // namespace rbfmuscle
