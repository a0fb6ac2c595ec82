#include "collision/contact_resolver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>

#include "collision/collision_error.h"
#include "collision/surface_probes.h"

namespace rbfmuscle {
namespace {

constexpr double kRestQueryRadiusMm = 1e6;
constexpr double kLowerBoundReachMm = 10.0;  ///< extra query radius so far probes get a useful lower bound
/// A moved centre k marks the probes within √(ln(1e3)/α_k) of it (where φ_k ≥ 1e-3) for re-projection.
const double kInfluenceLogRatio = std::log(1e3);
/// Centres with φ below this at a probe are left out of its constraint row (they barely act there).
constexpr double kDerivativeCutoff = 1e-3;
/// Smallest |cos(∇f, n)| taken as a push along the bone normal n (else inward along ∇f).
constexpr double kMinCosine = 0.3;

void requirePositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw CollisionError(std::string("ContactSettings: ") + name + " = " + std::to_string(value) + ", expected > 0");
}

void checkSettings(const ContactSettings& s) {
  requirePositive(s.tolerance_mm, "tolerance_mm");
  requirePositive(s.newton_step_cap_mm, "newton_step_cap_mm");
  requirePositive(s.projection_tolerance_mm, "projection_tolerance_mm");
  requirePositive(s.max_centre_step_mm, "max_centre_step_mm");
  requirePositive(s.safe_fraction, "safe_fraction");
  requirePositive(s.thickness_step_mm, "thickness_step_mm");
  requirePositive(s.thickness_max_mm, "thickness_max_mm");
  if (!(s.margin_mm >= 0.0)) throw CollisionError("ContactSettings: margin_mm = " + std::to_string(s.margin_mm) + ", expected ≥ 0");
  if (!(s.query_band_mm >= 0.0))
    throw CollisionError("ContactSettings: query_band_mm = " + std::to_string(s.query_band_mm) + ", expected ≥ 0");
  if (s.max_iterations < 0 || s.newton_steps < 0 || s.max_substeps < 1)
    throw CollisionError("ContactSettings: max_iterations " + std::to_string(s.max_iterations) + ", newton_steps " +
                         std::to_string(s.newton_steps) + ", max_substeps " + std::to_string(s.max_substeps) +
                         ": expected ≥ 0, ≥ 0, ≥ 1");
  if (s.thickness_max_mm < s.thickness_step_mm)
    throw CollisionError("ContactSettings: thickness_max_mm < thickness_step_mm");
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

ContactResolver::ContactResolver(std::vector<ContactBone> bones, const GaussianField& rest_field,
                                 const Eigen::Matrix3Xd& rest_probes_M, std::vector<bool> free_centres,
                                 const ContactSettings& settings)
    : bones_(std::move(bones)), free_centres_(std::move(free_centres)), settings_(settings) {
  checkSettings(settings_);
  if (bones_.empty()) throw CollisionError("ContactResolver: no bone");
  if (rest_probes_M.cols() < 1 || !rest_probes_M.allFinite())
    throw CollisionError("ContactResolver: " + std::to_string(rest_probes_M.cols()) +
                         " probes, expected ≥ 1 finite probe point");
  if (static_cast<int>(free_centres_.size()) != rest_field.getNumCentres())
    throw CollisionError("ContactResolver: free-centre mask of size " + std::to_string(free_centres_.size()) +
                         ", the field has " + std::to_string(rest_field.getNumCentres()) + " centres");
  const int P = static_cast<int>(rest_probes_M.cols()), B = countBones();
  for (ContactBone& bone : bones_) {
    BoneSet set;
    set.addBone(bone.name, bone.mesh_B);
    set.setBoneTransforms({bone.X_MB_rest});
    bone_sets_.push_back(std::move(set));
    X_MB_prev_.push_back(bone.X_MB_rest);
  }
  probes_M_ = rest_probes_M;
  thickness_mm_.resize(P);
  for (int i = 0; i < P; ++i) {
    Eigen::Vector3d p = probes_M_.col(i);
    projectOntoSurface(rest_field, p, 20, settings_.newton_step_cap_mm, settings_.projection_tolerance_mm);
    probes_M_.col(i) = p;
    thickness_mm_(i) = calcLocalThickness(rest_field, p, settings_.thickness_step_mm, settings_.thickness_max_mm);
  }
  carried_prev_M_ = rest_probes_M;
  rest_distance_mm_.resize(P, B);
  ref_point_B_.resize(static_cast<size_t>(B));
  for (int b = 0; b < B; ++b) {
    bone_sets_[static_cast<size_t>(b)].queryProbes(probes_M_, kRestQueryRadiusMm, query_out_);
    for (int i = 0; i < P; ++i) {
      const ContactQueryResult& q = query_out_[static_cast<size_t>(i)];
      rest_distance_mm_(i, b) = q.bone < 0 ? kRestQueryRadiusMm : q.signed_distance_mm;
    }
    ref_point_B_[static_cast<size_t>(b)] = bones_[static_cast<size_t>(b)].X_MB_rest.inverse() * probes_M_;
  }
  allowance_mm_ = rest_distance_mm_.unaryExpr(
      [](double s) { return s < 0.0 ? std::numeric_limits<double>::infinity() : 0.0; });
  ref_distance_mm_ = rest_distance_mm_;
  excess_mm_ = Eigen::VectorXd::Constant(P, -std::numeric_limits<double>::infinity());
  moved_.assign(free_centres_.size(), false);
  slack_mm_ = Eigen::VectorXd::Zero(P);
  exit_normal_M_ = Eigen::Matrix3Xd::Zero(3, P);
}

int ContactResolver::calcSubsteps(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::Matrix3Xd& carried_M) const {
  if (static_cast<int>(X_MB.size()) != countBones() || carried_M.cols() != probes_M_.cols())
    throw CollisionError("ContactResolver::calcSubsteps: " + std::to_string(X_MB.size()) + " poses and " +
                         std::to_string(carried_M.cols()) + " probes, expected " + std::to_string(countBones()) +
                         " and " + std::to_string(countProbes()));
  double needed = 1.0;
  for (int b = 0; b < countBones(); ++b) {
    const Eigen::Isometry3d X_BM_now = X_MB[static_cast<size_t>(b)].inverse();
    const Eigen::Isometry3d X_BM_prev = X_MB_prev_[static_cast<size_t>(b)].inverse();
    const Eigen::Matrix3Xd& ref = ref_point_B_[static_cast<size_t>(b)];
    for (int i = 0; i < countProbes(); ++i) {
      const Eigen::Vector3d p_prev_B = X_BM_prev * probes_M_.col(i);
      const Eigen::Vector3d x = probes_M_.col(i) + (carried_M.col(i) - carried_prev_M_.col(i));
      const double delta = (X_BM_now * x - p_prev_B).norm();
      const double bound_prev = ref_distance_mm_(i, b) - (p_prev_B - ref.col(i)).norm();
      if (bound_prev + allowance_mm_(i, b) < delta)
        needed = std::max(needed, delta / (settings_.safe_fraction *
                                           std::min(thickness_mm_(i), bones_[static_cast<size_t>(b)].thickness_mm)));
    }
  }
  return static_cast<int>(std::min<double>(settings_.max_substeps, std::ceil(needed - 1e-12)));
}

const ContactReport& ContactResolver::resolve(const std::vector<Eigen::Isometry3d>& X_MB,
                                              const Eigen::Matrix3Xd& carried_M, GaussianField& field, bool respond) {
  if (static_cast<int>(X_MB.size()) != countBones() || carried_M.cols() != probes_M_.cols() ||
      field.getNumCentres() != static_cast<int>(free_centres_.size()))
    throw CollisionError("ContactResolver::resolve: " + std::to_string(X_MB.size()) + " poses, " +
                         std::to_string(carried_M.cols()) + " probes, " + std::to_string(field.getNumCentres()) +
                         " centres; expected " + std::to_string(countBones()) + ", " + std::to_string(countProbes()) +
                         ", " + std::to_string(free_centres_.size()));
  const auto start = std::chrono::steady_clock::now();
  for (int b = 0; b < countBones(); ++b) bone_sets_[static_cast<size_t>(b)].setBoneTransforms({X_MB[static_cast<size_t>(b)]});
  X_MB_prev_ = X_MB;
  probes_M_ += carried_M - carried_prev_M_;
  carried_prev_M_ = carried_M;
  std::fill(moved_.begin(), moved_.end(), false);
  report_ = ContactReport{};

  double penetration = measure(field);
  report_.contacts = static_cast<int>((excess_mm_.array() > 0.0).count());
  report_.max_penetration_before_mm = penetration;
  if (!respond) {
    report_.stop = ContactStop::kMeasureOnly;
  } else {
    report_.stop = ContactStop::kWithinTolerance;
    while (penetration > settings_.tolerance_mm) {
      if (report_.iterations >= settings_.max_iterations) {
        report_.stop = ContactStop::kIterationCap;
        break;
      }
      if (!respondOnce(field)) {
        report_.stop = ContactStop::kNoFreeCentre;
        break;
      }
      ++report_.iterations;
      penetration = measure(field);
    }
  }
  report_.max_penetration_mm = penetration;
  report_.moved_centres = static_cast<int>(std::count(moved_.begin(), moved_.end(), true));
  report_.ms = msSince(start);
  return report_;
}

double ContactResolver::measure(const GaussianField& field) {
  const int P = countProbes(), B = countBones();
  const double travel = settings_.newton_steps * settings_.newton_step_cap_mm;
  const double radius = settings_.query_band_mm + travel + kLowerBoundReachMm;
  excess_mm_.setConstant(-std::numeric_limits<double>::infinity());
  std::vector<Eigen::Isometry3d> X_BM(static_cast<size_t>(B));
  for (int b = 0; b < B; ++b) X_BM[static_cast<size_t>(b)] = X_MB_prev_[static_cast<size_t>(b)].inverse();
  // Certified lower bound of s_ib at the probe's position, from its last exact query.
  const auto bound = [&](int i, int b) {
    return ref_distance_mm_(i, b) -
           (X_BM[static_cast<size_t>(b)] * probes_M_.col(i) - ref_point_B_[static_cast<size_t>(b)].col(i)).norm();
  };
  const auto threshold = [&](int i, int b) { return -allowance_mm_(i, b) + settings_.query_band_mm; };
  project_index_.clear();
  for (int i = 0; i < P; ++i) {
    bool project = false;
    for (int b = 0; b < B && !project; ++b) project = bound(i, b) - travel - slack_mm_(i) < threshold(i, b);
    if (project) project_index_.push_back(i);
  }
  const int count = static_cast<int>(project_index_.size());
#pragma omp parallel for schedule(dynamic, 16)
  for (int k = 0; k < count; ++k) {  // independent per probe: results do not depend on the threads
    const int i = project_index_[static_cast<size_t>(k)];
    Eigen::Vector3d p = probes_M_.col(i);
    const int steps = settings_.newton_steps + static_cast<int>(std::ceil(slack_mm_(i) / settings_.newton_step_cap_mm));
    projectOntoSurface(field, p, steps, settings_.newton_step_cap_mm, settings_.projection_tolerance_mm);
    probes_M_.col(i) = p;
    slack_mm_(i) = 0.0;
  }
  report_.projections += count;
  double worst = 0.0;
  for (int b = 0; b < B; ++b) {
    query_index_.clear();
    for (int i = 0; i < P; ++i)
      if (bound(i, b) < threshold(i, b)) query_index_.push_back(i);
    if (query_index_.empty()) continue;
    query_points_.resize(3, static_cast<Eigen::Index>(query_index_.size()));
    for (size_t k = 0; k < query_index_.size(); ++k)
      query_points_.col(static_cast<Eigen::Index>(k)) = probes_M_.col(query_index_[k]);
    bone_sets_[static_cast<size_t>(b)].queryProbes(query_points_, radius, query_out_);
    report_.probe_queries += static_cast<long long>(query_index_.size());
    for (size_t k = 0; k < query_index_.size(); ++k) {
      const int i = query_index_[k];
      const ContactQueryResult& q = query_out_[k];
      const double s = q.bone < 0 ? radius : q.signed_distance_mm;
      ref_distance_mm_(i, b) = s;
      ref_point_B_[static_cast<size_t>(b)].col(i) = X_BM[static_cast<size_t>(b)] * probes_M_.col(i);
      const double e = -s - allowance_mm_(i, b);
      if (e > excess_mm_(i)) {
        excess_mm_(i) = e;
        exit_normal_M_.col(i) = q.bone < 0 ? Eigen::Vector3d::Zero() : q.normal_W;
      }
      worst = std::max(worst, e);
    }
  }
  return worst;
}

void ContactResolver::addSlack(const GaussianField& field, const std::vector<int>& centres,
                               const Eigen::Matrix3Xd& old_centres, double longest_mm) {
  // Probes within the influence radius of a moved centre (old or new place) may now be up to
  // the longest centre move away from the surface.
  Eigen::AlignedBox3d box;
  std::vector<double> reach(centres.size());
  for (size_t c = 0; c < centres.size(); ++c) {
    const int k = centres[c];
    reach[c] = std::sqrt(kInfluenceLogRatio / field.getShapes()(k)) +
               (field.getCentres().col(k) - old_centres.col(k)).norm();
    box.extend(old_centres.col(k) - Eigen::Vector3d::Constant(reach[c]));
    box.extend(old_centres.col(k) + Eigen::Vector3d::Constant(reach[c]));
  }
  for (int i = 0; i < countProbes(); ++i) {
    if (!box.contains(probes_M_.col(i))) continue;
    for (size_t c = 0; c < centres.size(); ++c) {
      if ((probes_M_.col(i) - old_centres.col(centres[c])).squaredNorm() <= reach[c] * reach[c]) {
        slack_mm_(i) += longest_mm;
        break;
      }
    }
  }
}

bool ContactResolver::respondOnce(GaussianField& field) {
  const Eigen::Matrix3Xd& xi = field.getCentres();
  const Eigen::VectorXd& lambda = field.getWeights();
  const Eigen::VectorXd& alpha = field.getShapes();
  std::vector<int> local(static_cast<size_t>(field.getNumCentres()), -1);
  std::vector<int> centres;  // local → global
  std::vector<Eigen::Triplet<double>> triplets;
  std::vector<double> rhs;
  ActiveCentres active;
  for (int i = 0; i < countProbes(); ++i) {
    const double e = excess_mm_(i);
    if (!(e > 0.0)) continue;
    const Eigen::Vector3d p = probes_M_.col(i);
    field.findActiveCentres(p, active);
    double f = field.getOffset();
    Eigen::Vector3d grad = Eigen::Vector3d::Zero();
    const int row = static_cast<int>(rhs.size());
    bool any_free = false;
    for (int a = 0; a < active.size(); ++a) {
      const int k = active.indices[static_cast<size_t>(a)];
      const double w = lambda(k) * active.phi[static_cast<size_t>(a)];
      const Eigen::Vector3d d = p - xi.col(k);
      f += w;
      grad -= 2.0 * alpha(k) * w * d;
      if (!free_centres_[static_cast<size_t>(k)] || active.phi[static_cast<size_t>(a)] < kDerivativeCutoff) continue;
      if (local[static_cast<size_t>(k)] < 0) {
        local[static_cast<size_t>(k)] = static_cast<int>(centres.size());
        centres.push_back(k);
      }
      const Eigen::Vector3d dfdxi = 2.0 * alpha(k) * w * d;  // ∂f(p)/∂ξ_k
      for (int c = 0; c < 3; ++c) triplets.emplace_back(row, 3 * local[static_cast<size_t>(k)] + c, dfdxi(c));
      any_free = true;
    }
    if (!any_free) continue;
    // The surface point should move by (e + margin) along the bone's outward normal n: to first
    // order f_new(p + δn) = 0, i.e. J Δξ = −f − δ ∇f·n. Near-tangent normals (|cos| < kMinCosine,
    // a bone edge through the side of the muscle) push the surface inward along ∇f instead.
    const double g = grad.norm();
    double cosine = g > 0.0 ? grad.dot(exit_normal_M_.col(i)) / g : 1.0;
    if (std::abs(cosine) < kMinCosine) cosine = kMinCosine;
    rhs.push_back(-f - (e + settings_.margin_mm) * g * cosine);
  }
  const int m = static_cast<int>(rhs.size()), n = 3 * static_cast<int>(centres.size());
  if (m == 0 || n == 0) return false;
  Eigen::SparseMatrix<double, Eigen::RowMajor> A(m, n);
  A.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::Map<const Eigen::VectorXd> r(rhs.data(), m);
  Eigen::VectorXd step;
  if (m <= n) {
    Eigen::MatrixXd G = Eigen::MatrixXd(A * A.transpose());
    const double mu = settings_.damping * G.trace() / m + std::numeric_limits<double>::min();
    G.diagonal().array() += mu;
    step = A.transpose() * G.ldlt().solve(r);
  } else {
    Eigen::MatrixXd G = Eigen::MatrixXd(A.transpose() * A);
    const double mu = settings_.damping * G.trace() / n + std::numeric_limits<double>::min();
    G.diagonal().array() += mu;
    step = G.ldlt().solve(A.transpose() * r);
  }
  if (!step.allFinite()) return false;
  double longest = 0.0;
  for (size_t c = 0; c < centres.size(); ++c) longest = std::max(longest, step.segment<3>(3 * static_cast<Eigen::Index>(c)).norm());
  if (longest > settings_.max_centre_step_mm) step *= settings_.max_centre_step_mm / longest;
  const Eigen::Matrix3Xd old_centres = xi;
  Eigen::Matrix3Xd moved_centres = xi;
  for (size_t c = 0; c < centres.size(); ++c) {
    moved_centres.col(centres[c]) += step.segment<3>(3 * static_cast<Eigen::Index>(c));
    moved_[static_cast<size_t>(centres[c])] = true;
  }
  field.setCentrePositions(moved_centres);
  addSlack(field, centres, old_centres, std::min(longest, settings_.max_centre_step_mm));
  return true;
}

}  // namespace rbfmuscle
