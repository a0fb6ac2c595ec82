#include "collision/surface_probes.h"

#include "rbf/gaussian_terms.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace rbfmuscle {
namespace {

/// Indices of the vertices kept by a grid of cell h: per occupied cell the vertex nearest
/// its centre, in vertex order.
std::vector<int> pickOnePerCell(const Eigen::Matrix3Xd& v, const Eigen::Vector3d& lo, double h) {
  struct Best {
    int vertex;
    double d2;
  };
  std::unordered_map<long long, Best> cells;
  cells.reserve(static_cast<size_t>(v.cols()));
  for (Eigen::Index j = 0; j < v.cols(); ++j) {
    const Eigen::Vector3d c = (v.col(j) - lo) / h;
    const Eigen::Vector3d cell = c.array().floor();
    const long long key = (static_cast<long long>(cell.x()) * 1000003LL + static_cast<long long>(cell.y())) * 1000033LL +
                          static_cast<long long>(cell.z());
    const double d2 = (c - cell - Eigen::Vector3d::Constant(0.5)).squaredNorm();
    auto [it, inserted] = cells.emplace(key, Best{static_cast<int>(j), d2});
    if (!inserted && d2 < it->second.d2) it->second = Best{static_cast<int>(j), d2};
  }
  std::vector<int> kept;
  kept.reserve(cells.size());
  for (const auto& [key, best] : cells) kept.push_back(best.vertex);
  std::sort(kept.begin(), kept.end());
  return kept;
}

}  // namespace

Eigen::Matrix3Xd sampleSurfaceProbes(const TriangleMesh& surface, int count) {
  if (count < 1) throw std::invalid_argument("sampleSurfaceProbes: count " + std::to_string(count) + ", expected ≥ 1");
  const Eigen::Matrix3Xd& v = surface.vertices_mm;
  if (v.cols() == 0) throw std::invalid_argument("sampleSurfaceProbes: the surface has no vertex");
  if (v.cols() <= count) return v;
  const Eigen::AlignedBox3d box = surface.calcBoundingBox();
  const Eigen::Vector3d lo = box.min();
  // Bisection on log h between a cell that keeps ≥ count cells and one keeping fewer.
  double h_small = 1e-6 * (box.diagonal().norm() + 1.0), h_large = 2.0 * box.diagonal().norm() + 1.0;
  std::vector<int> best = pickOnePerCell(v, lo, h_large);
  for (int step = 0; step < 30; ++step) {
    const double h = std::sqrt(h_small * h_large);
    std::vector<int> kept = pickOnePerCell(v, lo, h);
    if (static_cast<int>(kept.size()) > count) {
      h_small = h;
    } else {
      h_large = h;
      best = std::move(kept);
      if (static_cast<int>(best.size()) == count) break;
    }
  }
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(best.size()));
  for (size_t k = 0; k < best.size(); ++k) out.col(static_cast<Eigen::Index>(k)) = v.col(best[k]);
  return out;
}

double calcValueAndGradient(const GaussianField& field, const Eigen::Vector3d& x_mm, Eigen::Vector3d& gradient) {
  thread_local ActiveCentres active;
  field.findActiveCentres(x_mm, active);
  const Eigen::Matrix3Xd& xi = field.getCentres();
  const Eigen::VectorXd& lambda = field.getWeights();
  const Eigen::VectorXd& alpha = field.getShapes();
  double f = field.getOffset();
  gradient.setZero();
  for (int a = 0; a < active.size(); ++a) {
    const int k = active.indices[static_cast<size_t>(a)];
    const double w = lambda(k) * active.phi[static_cast<size_t>(a)];
    f += w;
    gradient -= (2.0 * alpha(k) * w) * (x_mm - xi.col(k));
  }
  return f;
}

bool projectOntoSurface(const GaussianField& field, Eigen::Vector3d& x_mm, int max_steps, double step_cap_mm,
                        double tolerance_mm, Eigen::Vector3d* gradient) {
  return projectOntoSurfaceWith(
      [&](const Eigen::Vector3d& x, Eigen::Vector3d& g) { return calcValueAndGradient(field, x, g); }, x_mm, max_steps,
      step_cap_mm, tolerance_mm, gradient);
}

void LocalFieldEvaluator::collect(const GaussianField& field, const Eigen::VectorXd& cutoff_radius_mm,
                                  const Eigen::Vector3d& c_mm, double radius_mm, const std::vector<int>* among) {
  log_inv_cutoff_ = -std::log(field.getCutoff());  // as GaussianField::setCutoff
  const Eigen::Matrix3Xd& xi = field.getCentres();
  candidates_.resize(among ? among->size() : static_cast<size_t>(field.getNumCentres()));
  size_t kept = 0;
  // 1e-9 relative slack: a superset is harmless (the exact test runs per evaluation). Written
  // without a branch (the index is stored, and kept only if inside): about half of the centres
  // pass, a branch on it is mispredicted half the time.
  const auto consider = [&](int k) {
    const double reach = (cutoff_radius_mm(k) + radius_mm) * (1.0 + 1e-9) + 1e-9;
    candidates_[kept] = k;
    kept += (xi.col(k) - c_mm).squaredNorm() <= reach * reach ? 1 : 0;
  };
  if (among) {
    for (int k : *among) consider(k);
  } else {
    for (int k = 0; k < field.getNumCentres(); ++k) consider(k);
  }
  candidates_.resize(kept);
  offset_ = field.getOffset();
  centres_.resize(kept);
  for (size_t a = 0; a < kept; ++a) {
    const int k = candidates_[a];
    centres_[a] = Centre{xi(0, k), xi(1, k), xi(2, k), field.getShapes()(k), field.getWeights()(k)};
  }
}

double LocalFieldEvaluator::operator()(const Eigen::Vector3d& x_mm, Eigen::Vector3d& gradient) const {
  double f = offset_;
  gradient.setZero();
  for (const Centre& c : centres_) {
    const Eigen::Vector3d d = x_mm - Eigen::Vector3d(c.x, c.y, c.z);
    const double r2 = d.squaredNorm();
    if (!(c.alpha * r2 <= log_inv_cutoff_)) continue;
    const double w = c.lambda * gaussian::calcPhi(c.alpha, r2);
    f += w;
    gradient -= (2.0 * c.alpha * w) * d;
  }
  return f;
}

double marchToSurface(const GaussianField& field, const Eigen::Vector3d& start_mm, const Eigen::Vector3d& direction,
                      double step_mm, double max_mm) {
  if (!(step_mm > 0.0) || !(max_mm >= step_mm))
    throw std::invalid_argument("marchToSurface: step " + std::to_string(step_mm) + " mm, max " +
                                std::to_string(max_mm) + " mm; expected 0 < step ≤ max");
  double inside = 0.0;  // last distance with f > 0 (or the start)
  for (double t = step_mm; t <= max_mm; t += step_mm) {
    if (field.calcValue(start_mm + t * direction) > 0.0) {
      inside = t;
      continue;
    }
    double a = inside, b = t;  // f(a) > 0 (or a = 0), f(b) ≤ 0
    for (int k = 0; k < 20; ++k) {
      const double m = 0.5 * (a + b);
      (field.calcValue(start_mm + m * direction) > 0.0 ? a : b) = m;
    }
    return b;
  }
  return max_mm;
}

double calcLocalThickness(const GaussianField& field, const Eigen::Vector3d& p_mm, double step_mm, double max_mm) {
  if (!(step_mm > 0.0) || !(max_mm >= step_mm))
    throw std::invalid_argument("calcLocalThickness: step " + std::to_string(step_mm) + " mm, max " +
                                std::to_string(max_mm) + " mm; expected 0 < step ≤ max");
  const Eigen::Vector3d g = field.calcGradient(p_mm);
  if (!(g.squaredNorm() > 1e-24)) return max_mm;
  return marchToSurface(field, p_mm, g.normalized(), step_mm, max_mm);
}

}  // namespace rbfmuscle
