// SPDX-License-Identifier: Apache-2.0
#include "fibres/fibre_generator.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <cstdio>
#include <string>

namespace rbfmuscle {

double estimateSpreadingPairs(const FibreSettings& s) {
  return static_cast<double>(std::max(s.smoothing_iterations, 0)) * static_cast<double>(s.count) *
         static_cast<double>(s.count) * (kShapeSegments - 1);
}

namespace {

void checkSettings(const FibreSettings& s) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("FibreSettings: " + what); };
  if (s.count < 1) fail("count must be ≥ 1, got " + std::to_string(s.count));
  if (s.segments < 1) fail("segments must be ≥ 1, got " + std::to_string(s.segments));
  if (!(s.attachment_radius_mm > 0) || !std::isfinite(s.attachment_radius_mm))
    fail("attachment_radius_mm must be > 0, got " + std::to_string(s.attachment_radius_mm));
  if (s.grid_nodes < 8) fail("grid_nodes must be ≥ 8, got " + std::to_string(s.grid_nodes));
  if (!(s.centre_preference >= 0)) fail("centre_preference must be ≥ 0, got " + std::to_string(s.centre_preference));
  if (!(s.spreading >= 0) || !std::isfinite(s.spreading)) fail("spreading must be ≥ 0, got " + std::to_string(s.spreading));
  if (s.smoothing_iterations < 0) fail("smoothing_iterations must be ≥ 0, got " + std::to_string(s.smoothing_iterations));
  if (!std::isfinite(s.end_depth)) fail("end_depth must be finite, got " + std::to_string(s.end_depth));
  checkProjectionSettings(s.projection);
  const double points = static_cast<double>(s.count) * (s.segments + 1.0);
  if (points > kMaxFibrePoints)
    fail("count " + std::to_string(s.count) + " × (segments " + std::to_string(s.segments) + " + 1) = " +
         std::to_string(static_cast<long long>(points)) + " fibre points, more than the " +
         std::to_string(static_cast<long long>(kMaxFibrePoints)) +
         " that can be tracked (each is moved and projected every frame); use fewer fibres or segments");
  const double pairs = estimateSpreadingPairs(s);
  if (pairs > kMaxSpreadingPairs) {
    char text[64];
    std::snprintf(text, sizeof text, "%.3g", pairs);
    char bound[64];
    std::snprintf(bound, sizeof bound, "%.3g", kMaxSpreadingPairs);
    fail("count " + std::to_string(s.count) + " and " + std::to_string(s.smoothing_iterations) +
         " relaxation rounds need about " + text + " point-pair evaluations to generate the fibres, more than the " +
         bound + " allowed (a minute or two); use fewer fibres or relaxation rounds");
  }
}

/// Distance from p to the nearest region point (mm).
double distanceToRegion(const Eigen::Vector3d& p, const Eigen::Matrix3Xd& region) {
  return std::sqrt((region.colwise() - p).colwise().squaredNorm().minCoeff());
}

/// The region point nearest p.
Eigen::Vector3d findNearestRegionPoint(const Eigen::Vector3d& p, const Eigen::Matrix3Xd& region) {
  Eigen::Index nearest = 0;
  (region.colwise() - p).colwise().squaredNorm().minCoeff(&nearest);
  return region.col(nearest);
}

/// N fibre ends spread over the attachment near `region` (file comment, step 2), among the
/// `allowed` nodes; `distance` holds each node's distance to the region (mm).
std::vector<int> chooseEnds(const InteriorGrid& grid, const Eigen::Matrix3Xd& region, const Eigen::VectorXd& distance,
                            const std::vector<char>& allowed, int count, double radius, double end_depth,
                            const char* which, double& used_radius) {
  const Eigen::Index n = grid.nodes_mm.cols();
  std::vector<int> candidates, deep;
  for (int growth = 0; growth <= 8; ++growth, radius *= 1.5) {
    candidates.clear();
    deep.clear();
    for (Eigen::Index a = 0; a < n; ++a)
      if (allowed[static_cast<size_t>(a)] && distance(a) <= radius) {
        candidates.push_back(static_cast<int>(a));
        if (grid.values(a) >= end_depth) deep.push_back(static_cast<int>(a));
      }
    if (!candidates.empty()) break;
  }
  if (candidates.empty())
    throw std::invalid_argument(std::string("generateFibres: no interior grid node near the ") + which +
                                " region (radius " + std::to_string(radius) + " mm)");
  used_radius = radius;
  // Deep nodes only when there are enough of them at this radius, else the `count`
  // deepest (all, when fewer): the shallow ones are the first to fall outside when the
  // surface near the attachment moves.
  if (static_cast<int>(deep.size()) >= count) {
    candidates.swap(deep);
  } else if (static_cast<int>(candidates.size()) > count) {
    std::stable_sort(candidates.begin(), candidates.end(), [&](int a, int b) { return grid.values(a) > grid.values(b); });
    candidates.resize(static_cast<size_t>(count));
    std::sort(candidates.begin(), candidates.end());
  }
  // Farthest-point sampling from the candidate nearest the first region point; with fewer
  // candidates than fibres, the fibres share them in that order.
  int first = candidates[0];
  double best = std::numeric_limits<double>::infinity();
  for (int a : candidates) {
    const double d = (grid.nodes_mm.col(a) - region.col(0)).squaredNorm();
    if (d < best) best = d, first = a;
  }
  std::vector<int> chosen{first};
  std::vector<double> nearest(candidates.size(), std::numeric_limits<double>::infinity());
  while (chosen.size() < std::min(candidates.size(), static_cast<size_t>(count))) {
    size_t far = 0;
    double far_d = -1;
    for (size_t c = 0; c < candidates.size(); ++c) {
      nearest[c] = std::min(nearest[c], (grid.nodes_mm.col(candidates[c]) - grid.nodes_mm.col(chosen.back())).squaredNorm());
      if (nearest[c] > far_d) far_d = nearest[c], far = c;
    }
    chosen.push_back(candidates[far]);
  }
  for (size_t i = chosen.size(); i < static_cast<size_t>(count); ++i) chosen.push_back(chosen[i % candidates.size()]);
  return chosen;
}

/// Each node's distance to the region (mm).
Eigen::VectorXd calcDistancesToRegion(const InteriorGrid& grid, const Eigen::Matrix3Xd& region, const char* which) {
  if (region.cols() == 0 || !region.allFinite())
    throw std::invalid_argument(std::string("generateFibres: the ") + which + " region needs ≥ 1 finite point");
  Eigen::VectorXd distance(grid.nodes_mm.cols());
  for (Eigen::Index a = 0; a < distance.size(); ++a) distance(a) = distanceToRegion(grid.nodes_mm.col(a), region);
  return distance;
}

/// The interior grid, the nodes of the piece the fibres run through and their distances to
/// the two regions (file comment, step 1).
struct FibreGrid {
  InteriorGrid grid;
  std::vector<char> in_piece;
  Eigen::VectorXd to_origin, to_insertion;
  int refinements = 0;
};

/// @throws std::runtime_error when no piece reaches both regions on the finest grid.
FibreGrid makeFibreGrid(const GaussianField& field, const Eigen::Matrix3Xd& origin, const Eigen::Matrix3Xd& insertion,
                        const FibreSettings& settings) {
  for (int refinement = 0;; ++refinement) {
    FibreGrid g;
    g.refinements = refinement;
    const long long nodes = static_cast<long long>(settings.grid_nodes) << refinement;
    g.grid = makeInteriorGrid(field, settings.projection.margin_mm,
                              static_cast<int>(std::min<long long>(nodes, std::numeric_limits<int>::max())));
    g.to_origin = calcDistancesToRegion(g.grid, origin, "origin");
    g.to_insertion = calcDistancesToRegion(g.grid, insertion, "insertion");
    int count = 0;
    const std::vector<int> piece = labelInteriorPieces(g.grid, count);
    // A piece reaches a region when it comes within r of where the whole inside comes nearest.
    const double reach_origin = g.to_origin.minCoeff() + settings.attachment_radius_mm;
    const double reach_insertion = g.to_insertion.minCoeff() + settings.attachment_radius_mm;
    std::vector<double> near_origin(static_cast<size_t>(count), std::numeric_limits<double>::infinity());
    std::vector<double> near_insertion = near_origin;
    std::vector<int> size(static_cast<size_t>(count), 0);
    for (size_t a = 0; a < piece.size(); ++a) {
      const size_t p = static_cast<size_t>(piece[a]);
      near_origin[p] = std::min(near_origin[p], g.to_origin(static_cast<Eigen::Index>(a)));
      near_insertion[p] = std::min(near_insertion[p], g.to_insertion(static_cast<Eigen::Index>(a)));
      ++size[p];
    }
    int chosen = -1;
    for (int p = 0; p < count; ++p)
      if (near_origin[static_cast<size_t>(p)] <= reach_origin &&
          near_insertion[static_cast<size_t>(p)] <= reach_insertion &&
          (chosen < 0 || size[static_cast<size_t>(p)] > size[static_cast<size_t>(chosen)]))
        chosen = p;
    if (chosen >= 0) {
      g.in_piece.resize(piece.size());
      for (size_t a = 0; a < piece.size(); ++a) g.in_piece[a] = piece[a] == chosen;
      return g;
    }
    if (refinement == kMaxGridRefinements) {
      char text[160];
      std::snprintf(text, sizeof text, "a grid of spacing %.3g mm (%lld nodes inside, in %d pieces)", g.grid.spacing_mm,
                    static_cast<long long>(g.grid.nodes_mm.cols()), count);
      throw std::runtime_error(std::string("generateFibres: no piece of the inside {f >= margin} reaches both the origin "
                                           "and the insertion region, even on ") + text +
                               ": the muscle is in pieces, or a part of it is thinner than that spacing");
    }
  }
}

/// Moves each end (3×N) up the field towards f = end_depth, by at most `max_move_mm` (file
/// comment, step 2).
void climbEnds(const GaussianField& field, const FibreSettings& settings, double max_move_mm, Eigen::Matrix3Xd& ends) {
  if (!(settings.end_depth > settings.projection.margin_mm)) return;
  ProjectionSettings climb = settings.projection;
  climb.margin_mm = settings.end_depth;
  for (Eigen::Index i = 0; i < ends.cols(); ++i) {
    Eigen::Vector3d p = ends.col(i);
    projectInside(field, climb, p, max_move_mm);
    ends.col(i) = p;
  }
}

/// Orders `points` (3×N) by strips of u then v (file comment, step 3).
std::vector<int> orderByStrips(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2) {
  const Eigen::Index n = points.cols();
  const Eigen::Vector3d mean = points.rowwise().mean();
  Eigen::VectorXd u = e1.transpose() * (points.colwise() - mean), v = e2.transpose() * (points.colwise() - mean);
  const auto normalise = [](Eigen::VectorXd& x) {
    const double sd = std::sqrt(x.squaredNorm() / static_cast<double>(x.size()));
    if (sd > 0) x /= sd;
  };
  normalise(u);
  normalise(v);
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return u(a) < u(b); });
  const int strip = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  for (Eigen::Index s = 0; s < n; s += strip) {
    const auto begin = order.begin() + s, end = order.begin() + std::min<Eigen::Index>(n, s + strip);
    std::stable_sort(begin, end, [&](int a, int b) { return v(a) < v(b); });
  }
  return order;
}

/// The polyline through `nodes` resampled to `segments` equal arc-length segments.
Eigen::Matrix3Xd resample(const Eigen::Matrix3Xd& polyline, int segments) {
  const Eigen::Index m = polyline.cols();
  std::vector<double> arc(static_cast<size_t>(m), 0.0);
  for (Eigen::Index k = 1; k < m; ++k)
    arc[static_cast<size_t>(k)] = arc[static_cast<size_t>(k - 1)] + (polyline.col(k) - polyline.col(k - 1)).norm();
  Eigen::Matrix3Xd out(3, segments + 1);
  size_t k = 0;
  for (int j = 0; j <= segments; ++j) {
    const double s = arc.back() * j / segments;
    while (k + 2 < static_cast<size_t>(m) && arc[k + 1] < s) ++k;
    if (m == 1) {
      out.col(j) = polyline.col(0);
      continue;
    }
    const double span = arc[k + 1] - arc[k];
    const double t = span > 0 ? std::clamp((s - arc[k]) / span, 0.0, 1.0) : 0.0;
    out.col(j) = (1 - t) * polyline.col(static_cast<Eigen::Index>(k)) + t * polyline.col(static_cast<Eigen::Index>(k + 1));
  }
  out.col(0) = polyline.col(0);
  out.col(segments) = polyline.col(m - 1);
  return out;
}

/// Distance from p to the segment [a, b] (mm).
double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

void measureCoverage(const InteriorGrid& grid, RestFibres& fibres) {
  Eigen::VectorXd inside_lengths_mm;  // without the tendons, which need not run through the volume
  calcFibreLengths(fibres.points_mm, fibres.segments, inside_lengths_mm);
  const double total_length = inside_lengths_mm.sum();
  fibres.ideal_radius_mm = std::sqrt(grid.calcVolume() / (M_PI * std::max(total_length, 1e-12)));
  const Eigen::Index n = grid.nodes_mm.cols();
  const Eigen::Index stride = std::max<Eigen::Index>(1, n / 4000);
  const int per = fibres.segments + 1;
  double sum = 0;
  int covered = 0, measured = 0;
  for (Eigen::Index a = 0; a < n; a += stride, ++measured) {
    double d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < fibres.count; ++i)
      for (int j = 0; j < fibres.segments; ++j)
        d = std::min(d, distanceToSegment(grid.nodes_mm.col(a), fibres.points_mm.col(i * per + j),
                                          fibres.points_mm.col(i * per + j + 1)));
    sum += d;
    covered += d <= 2.0 * fibres.ideal_radius_mm;
  }
  fibres.mean_distance_mm = sum / measured;
  fibres.covered_fraction = static_cast<double>(covered) / measured;
}

}  // namespace

RestFibres generateFibres(const GaussianField& field, const Eigen::Matrix3Xd& origin_region_mm,
                          const Eigen::Matrix3Xd& insertion_region_mm, const FibreSettings& settings) {
  checkSettings(settings);
  const FibreGrid fibre_grid = makeFibreGrid(field, origin_region_mm, insertion_region_mm, settings);
  const InteriorGrid& grid = fibre_grid.grid;
  RestFibres fibres;
  fibres.count = settings.count;
  fibres.segments = settings.segments;
  fibres.grid_spacing_mm = grid.spacing_mm;
  fibres.grid_refinements = fibre_grid.refinements;
  const std::vector<int> starts =
      chooseEnds(grid, origin_region_mm, fibre_grid.to_origin, fibre_grid.in_piece, settings.count,
                 settings.attachment_radius_mm, settings.end_depth, "origin", fibres.attachment_radius_origin_mm);
  const std::vector<int> ends =
      chooseEnds(grid, insertion_region_mm, fibre_grid.to_insertion, fibre_grid.in_piece, settings.count,
                 settings.attachment_radius_mm, settings.end_depth, "insertion", fibres.attachment_radius_insertion_mm);
  Eigen::Matrix3Xd p0(3, settings.count), p1(3, settings.count);
  for (int i = 0; i < settings.count; ++i) {
    p0.col(i) = grid.nodes_mm.col(starts[static_cast<size_t>(i)]);
    p1.col(i) = grid.nodes_mm.col(ends[static_cast<size_t>(i)]);
  }
  fibres.end_climb_max_mm = 0.5 * grid.spacing_mm;
  climbEnds(field, settings, fibres.end_climb_max_mm, p0);
  climbEnds(field, settings, fibres.end_climb_max_mm, p1);
  // Pairing axes (file comment, step 3).
  Eigen::Vector3d d = p1.rowwise().mean() - p0.rowwise().mean();
  d = d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::UnitZ();
  const Eigen::Matrix3d to_plane = Eigen::Matrix3d::Identity() - d * d.transpose();
  const Eigen::Matrix3Xd q = to_plane * (p0.colwise() - p0.rowwise().mean());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(q * q.transpose());
  Eigen::Vector3d e1 = eig.eigenvectors().col(2);
  if (e1.squaredNorm() < 1e-24 || std::abs(e1.dot(d)) > 0.999) e1 = d.unitOrthogonal();
  e1 = (to_plane * e1).normalized();
  const Eigen::Vector3d e2 = d.cross(e1);
  const std::vector<int> order0 = orderByStrips(p0, e1, e2), order1 = orderByStrips(p1, e1, e2);

  // The shape is made at kShapeSegments (steps 4–5), then sampled at S (step 6).
  const int per = kShapeSegments + 1;
  fibres.points_mm.resize(3, static_cast<Eigen::Index>(settings.count) * per);
  for (int i = 0; i < settings.count; ++i) {
    const int a = starts[static_cast<size_t>(order0[static_cast<size_t>(i)])];
    const int b = ends[static_cast<size_t>(order1[static_cast<size_t>(i)])];
    const std::vector<int> path = findShortestPath(grid, a, b, settings.centre_preference);
    Eigen::Matrix3Xd polyline(3, static_cast<Eigen::Index>(path.size()));
    for (size_t k = 0; k < path.size(); ++k) polyline.col(static_cast<Eigen::Index>(k)) = grid.nodes_mm.col(path[k]);
    polyline.col(0) = p0.col(order0[static_cast<size_t>(i)]);
    polyline.col(polyline.cols() - 1) = p1.col(order1[static_cast<size_t>(i)]);
    fibres.points_mm.middleCols(static_cast<Eigen::Index>(i) * per, per) = resample(polyline, kShapeSegments);
  }
  // Spreading scale: the radius r₀ each fibre would own, with the chords as lengths.
  const double chord = (p1.rowwise().mean() - p0.rowwise().mean()).norm();
  const double spread_mm = std::sqrt(grid.calcVolume() / (M_PI * settings.count * std::max(chord, grid.spacing_mm)));
  for (int round = 0; round < settings.smoothing_iterations; ++round) {
    const Eigen::Matrix3Xd before = fibres.points_mm;
    for (int i = 0; i < settings.count; ++i)
      for (int j = 1; j < kShapeSegments; ++j) {
        const Eigen::Index c = static_cast<Eigen::Index>(i) * per + j;
        const Eigen::Vector3d tangent = (before.col(c + 1) - before.col(c - 1)).normalized();
        Eigen::Vector3d push = Eigen::Vector3d::Zero();
        for (int k = 0; k < settings.count; ++k) {
          const Eigen::Vector3d d = before.col(c) - before.col(static_cast<Eigen::Index>(k) * per + j);
          const double r2 = d.squaredNorm();
          if (k == i || r2 > 9.0 * spread_mm * spread_mm || r2 == 0.0) continue;
          push += d / std::sqrt(r2) * std::exp(-0.5 * r2 / (spread_mm * spread_mm));
        }
        push -= push.dot(tangent) * tangent;
        push *= settings.spreading * 0.25 * spread_mm;
        if (push.norm() > spread_mm) push *= spread_mm / push.norm();
        Eigen::Vector3d p = before.col(c) + 0.5 * (0.5 * (before.col(c - 1) + before.col(c + 1)) - before.col(c)) + push;
        projectInside(field, settings.projection, p);
        fibres.points_mm.col(c) = p;
      }
  }
  if (settings.segments != kShapeSegments) {
    const Eigen::Matrix3Xd shapes = fibres.points_mm;
    const int sampled_per = settings.segments + 1;
    fibres.points_mm.resize(3, static_cast<Eigen::Index>(settings.count) * sampled_per);
    for (int i = 0; i < settings.count; ++i) {
      const Eigen::Index first = static_cast<Eigen::Index>(i) * sampled_per;
      fibres.points_mm.middleCols(first, sampled_per) =
          resample(shapes.middleCols(static_cast<Eigen::Index>(i) * per, per), settings.segments);
      for (int j = 1; j < settings.segments; ++j) {
        Eigen::Vector3d p = fibres.points_mm.col(first + j);
        projectInside(field, settings.projection, p);
        fibres.points_mm.col(first + j) = p;
      }
    }
  }
  // Tendons to the areas (file comment, step 7).
  const int sampled_per = settings.segments + 1;
  fibres.attachments_mm.resize(3, 2 * static_cast<Eigen::Index>(settings.count));
  for (int i = 0; i < settings.count; ++i) {
    const Eigen::Index first = static_cast<Eigen::Index>(i) * sampled_per;
    fibres.attachments_mm.col(2 * i) = findNearestRegionPoint(fibres.points_mm.col(first), origin_region_mm);
    fibres.attachments_mm.col(2 * i + 1) =
        findNearestRegionPoint(fibres.points_mm.col(first + settings.segments), insertion_region_mm);
  }
  Eigen::VectorXd values;
  field.calcValues(fibres.points_mm, values);
  fibres.min_value = values.minCoeff();
  fibres.points_below_margin = static_cast<int>((values.array() < settings.projection.margin_mm).count());
  calcFibreLengths(fibres.points_mm, fibres.segments, fibres.attachments_mm, fibres.lengths_mm);
  measureCoverage(grid, fibres);
  return fibres;
}

}  // namespace rbfmuscle
