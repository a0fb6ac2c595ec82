#include "collision/contact_resolver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Cholesky>

#include "collision/collision_error.h"
#include "collision/contact_dump.h"
#include <cstdlib>
#include <fstream>
#include "collision/surface_probes.h"
#include "rbf/spatial_grid.h"

namespace rbfmuscle {
namespace {

constexpr double kRestQueryRadiusMm = 1e6;
constexpr double kLowerBoundReachMm = 10.0;  ///< extra query radius so far probes get a useful lower bound
constexpr double kGroupCellMm = 10.0;  ///< cell of the probe groups sharing a list of centres (projection)
constexpr double kGroupsPerBlock = 4.0;  ///< block edge in group cells: groups collect from their block's list
/// A probe counts for the deepest penetration only where it is on the surface, |f|/‖∇f‖ ≤ this (mm).
constexpr double kOnSurfaceMm = 0.05;
/// Newton steps of the second projection of a deepest probe left off the surface.
constexpr int kRescueSteps = 30;
/// Uncovered contacts: bone vertices are tested within this of a probe near the bone (mm), and
/// followed into the bone in steps of kSeatStepMm up to kSeatDepthMm to the muscle surface.
constexpr double kWatchReachMm = 10.0;
constexpr double kSeatStepMm = 0.25;
constexpr double kSeatDepthMm = 20.0;
/// A seat whose nearest probe within this many cover radii is excluded for the bone lies in the rest overlap.
constexpr double kOverlapReach = 3.0;
/// A moved centre k marks the probes within √(ln(1e3)/α_k) of it (where φ_k ≥ 1e-3) for re-projection.
const double kInfluenceLogRatio = std::log(1e3);

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
  requirePositive(s.cover_radius_mm, "cover_radius_mm");
  requirePositive(s.aim_below_tolerance_mm, "aim_below_tolerance_mm");
  if (!(s.query_band_mm >= 0.0))
    throw CollisionError("ContactSettings: query_band_mm = " + std::to_string(s.query_band_mm) + ", expected ≥ 0");
  if (s.max_iterations < 0 || s.newton_steps < 0 || s.max_substeps < 1 || s.max_reseats < 0)
    throw CollisionError("ContactSettings: max_iterations " + std::to_string(s.max_iterations) + ", newton_steps " +
                         std::to_string(s.newton_steps) + ", max_substeps " + std::to_string(s.max_substeps) +
                         ", max_reseats " + std::to_string(s.max_reseats) + ": expected ≥ 0, ≥ 0, ≥ 1, ≥ 0");
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
  if (const char* dir = std::getenv("RBFMUSCLE_CONTACT_DUMP")) {
    static int counter = 0;
    dump_ = std::make_shared<std::ofstream>(std::string(dir) + "/resolver_" + std::to_string(counter++) + ".bin", std::ios::binary);
    using namespace contact_dump;
    writeValue(*dump_, settings_);
    writeValue(*dump_, B);
    for (const ContactBone& bone : bones_) {
      writeValue(*dump_, static_cast<int>(bone.name.size()));
      dump_->write(bone.name.data(), static_cast<std::streamsize>(bone.name.size()));
      writeMatrix(*dump_, bone.mesh_B.vertices_mm);
      writeMatrix(*dump_, bone.mesh_B.triangles);
      writeMatrix(*dump_, Eigen::Matrix4d(bone.X_MB_rest.matrix()));
      writeValue(*dump_, bone.thickness_mm);
    }
    writeValue(*dump_, rest_field.getOffset());
    writeValue(*dump_, rest_field.getCutoff());
    writeMatrix(*dump_, rest_field.getCentres());
    writeMatrix(*dump_, rest_field.getWeights());
    writeMatrix(*dump_, rest_field.getShapes());
    writeMatrix(*dump_, rest_probes_M);
    Eigen::VectorXi mask(static_cast<Eigen::Index>(free_centres_.size()));
    for (size_t k = 0; k < free_centres_.size(); ++k) mask(static_cast<Eigen::Index>(k)) = free_centres_[k] ? 1 : 0;
    writeMatrix(*dump_, mask);
  }
  for (ContactBone& bone : bones_) {
    BoneSet set;
    set.addBone(bone.name, bone.mesh_B);
    // The certified bounds (class comment, Culling) already leave only probes near the bone;
    // BoneSet's own culling (answers unchanged either way) then only costs: 0.3-0.4 ms per
    // iliacus frame for its FCL cloud-sphere test.
    set.setBroadPhaseEnabled(false);
    set.setBoneTransforms({bone.X_MB_rest});
    bone_sets_.push_back(std::move(set));
    X_MB_prev_.push_back(bone.X_MB_rest);
  }
  {
    std::vector<TriangleMesh> meshes;
    std::vector<Eigen::Isometry3d> poses;
    for (const ContactBone& bone : bones_) {
      meshes.push_back(bone.mesh_B);
      poses.push_back(bone.X_MB_rest);
    }
    watch_ = BoneVertexWatch(meshes, poses, rest_field, 2.0 * settings_.cover_radius_mm);
  }
  probes_M_ = rest_probes_M;
  normal_M_ = Eigen::Matrix3Xd::Zero(3, P);
  thickness_mm_.resize(P);
  for (int i = 0; i < P; ++i) {
    Eigen::Vector3d p = probes_M_.col(i), g;
    projectOntoSurface(rest_field, p, 20, settings_.newton_step_cap_mm, settings_.projection_tolerance_mm, &g);
    probes_M_.col(i) = p;
    setNormal(i, g);
    thickness_mm_(i) = calcLocalThickness(rest_field, p, settings_.thickness_step_mm, settings_.thickness_max_mm);
  }
  free_share_.resize(P);
  ActiveCentres active;
  for (int i = 0; i < P; ++i) {
    free_share_(i) = calcFreeShare(rest_field, probes_M_.col(i), active);
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
  ref_upper_mm_ = rest_distance_mm_.unaryExpr(
      [](double s) { return s >= kRestQueryRadiusMm ? std::numeric_limits<double>::infinity() : s; });
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
    for (int i = 0; i < countProbes(); ++i) {
      const Eigen::Vector3d p_prev_B = X_BM_prev * probes_M_.col(i);
      const Eigen::Vector3d x = calcStartPoint(i, carried_M);
      const Eigen::Vector3d move_B = X_BM_now * x - p_prev_B;
      const double bound_prev = calcLowerBound(i, b, p_prev_B);
      if (!(bound_prev + allowance_mm_(i, b) < move_B.norm())) continue;
      // Only the move through the muscle, along its normal, can carry a bone point across its
      // thickness; sliding along the surface cannot (class comment, Tunnelling guard).
      const Eigen::Vector3d n_M = normal_M_.col(i);
      const double through = n_M.isZero() ? move_B.norm() : std::abs(move_B.dot(X_BM_now.linear() * n_M));
      needed = std::max(needed, through / (settings_.safe_fraction *
                                           std::min(thickness_mm_(i), bones_[static_cast<size_t>(b)].thickness_mm)));
    }
  }
  return static_cast<int>(std::min<double>(settings_.max_substeps, std::ceil(needed - 1e-12)));
}

const ContactReport& ContactResolver::resolve(const std::vector<Eigen::Isometry3d>& X_MB,
                                              const Eigen::Matrix3Xd& carried_M, GaussianField& field, bool respond) {
  return run(X_MB, carried_M, field, respond ? &field : nullptr);
}

const ContactReport& ContactResolver::resolveFrom(const std::vector<Eigen::Isometry3d>& X_MB,
                                                  const Eigen::Matrix3Xd& carried_M, const GaussianField& field,
                                                  GaussianField& work) {
  if (work.getNumCentres() != field.getNumCentres())
    throw CollisionError("ContactResolver::resolveFrom: work field of " + std::to_string(work.getNumCentres()) +
                         " centres, the field has " + std::to_string(field.getNumCentres()));
  return run(X_MB, carried_M, field, &work);
}

const ContactReport& ContactResolver::measureOnly(const std::vector<Eigen::Isometry3d>& X_MB,
                                                  const Eigen::Matrix3Xd& carried_M, const GaussianField& field) {
  return run(X_MB, carried_M, field, nullptr);
}

const ContactReport& ContactResolver::run(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::Matrix3Xd& carried_M,
                                          const GaussianField& measured, GaussianField* moved) {
  const bool respond = moved != nullptr;
  if (static_cast<int>(X_MB.size()) != countBones() || carried_M.cols() != probes_M_.cols() ||
      measured.getNumCentres() != static_cast<int>(free_centres_.size()))
    throw CollisionError("ContactResolver::resolve: " + std::to_string(X_MB.size()) + " poses, " +
                         std::to_string(carried_M.cols()) + " probes, " + std::to_string(measured.getNumCentres()) +
                         " centres; expected " + std::to_string(countBones()) + ", " + std::to_string(countProbes()) +
                         ", " + std::to_string(free_centres_.size()));
  if (dump_) {
    using namespace contact_dump;
    writeValue(*dump_, 1);
    writeValue(*dump_, respond ? 1 : 0);
    for (const Eigen::Isometry3d& X : X_MB) writeMatrix(*dump_, Eigen::Matrix4d(X.matrix()));
    writeMatrix(*dump_, carried_M);
    writeMatrix(*dump_, measured.getCentres());
    writeMatrix(*dump_, measured.getWeights());
    writeValue(*dump_, measured.getOffset());
    dump_->flush();
  }
  const auto start = std::chrono::steady_clock::now();
  for (int b = 0; b < countBones(); ++b) bone_sets_[static_cast<size_t>(b)].setBoneTransforms({X_MB[static_cast<size_t>(b)]});
  X_MB_prev_ = X_MB;
  // Probes follow the change of their carried points (class comment, Probes).
  for (int i = 0; i < countProbes(); ++i) probes_M_.col(i) = calcStartPoint(i, carried_M);
  carried_prev_M_ = carried_M;
  std::fill(moved_.begin(), moved_.end(), false);
  report_ = ContactReport{};
  watchBoneVertices(measured);

  // Measured first as when measuring only (the same contacts and depths with the least work);
  // most frames need no push, and only a response needs the query band's near probes.
  double penetration = measure(measured, true);
  report_.contacts = static_cast<int>((excess_mm_.array() > 0.0).count());
  report_.max_penetration_before_mm = penetration;
  const bool push = respond && penetration > settings_.tolerance_mm;
  report_.stop = respond ? ContactStop::kWithinTolerance : ContactStop::kMeasureOnly;
  if (push) {
    if (moved != &measured) {  // the push works on `moved`, made a copy of the measured field only now
      moved->setCentrePositions(measured.getCentres());
      moved->setWeights(measured.getWeights());
      moved->setOffset(measured.getOffset());
    }
    penetration = measure(*moved);
    // Trust region on the centre moves: doubled after a step that lowered the worst excess,
    // halved after one that did not, within [max_centre_step_mm / 8, 4 max_centre_step_mm].
    double step_limit = settings_.max_centre_step_mm;
    // The best iterate (lowest worst excess) is kept: a stopped response never leaves the
    // muscle deeper than its best state.
    double best = penetration;
    best_centres_ = moved->getCentres();
    best_probes_ = probes_M_;
    while (penetration > settings_.tolerance_mm) {
      if (report_.iterations >= settings_.max_iterations) {
        report_.stop = ContactStop::kIterationCap;
        break;
      }
      if (!respondOnce(*moved, step_limit)) {
        report_.stop = ContactStop::kNoFreeCentre;
        break;
      }
      ++report_.iterations;
      const double previous = penetration;
      penetration = measure(*moved);
      step_limit = penetration < previous ? std::min(2.0 * step_limit, 4.0 * settings_.max_centre_step_mm)
                                          : std::max(0.5 * step_limit, 0.125 * settings_.max_centre_step_mm);
      if (penetration < best) {
        best = penetration;
        best_centres_ = moved->getCentres();
        best_probes_ = probes_M_;
      }
    }
    if (penetration > best) {
      // Back to the best centres; every probe may be as far from the surface as the largest
      // centre move back (slack), so measure again.
      const double back = (moved->getCentres() - best_centres_).colwise().norm().maxCoeff();
      moved->setCentrePositions(best_centres_);
      probes_M_ = best_probes_;
      slack_mm_.array() += back;
      penetration = measure(*moved);
    }
  }
  report_.max_penetration_mm = penetration;
  report_.max_penetration_free_mm = push ? calcFreeSurfacePenetration(*moved) : free_penetration_mm_;
  report_.moved_centres = static_cast<int>(std::count(moved_.begin(), moved_.end(), true));
  report_.ms = msSince(start);
  return report_;
}

double ContactResolver::calcFreeSurfacePenetration(const GaussianField& field) {
  active_.clear();
  for (int i = 0; i < countProbes(); ++i)
    if (excess_mm_(i) > 0.0) active_.push_back(i);
  std::sort(active_.begin(), active_.end(), [&](int a, int b) { return excess_mm_(a) > excess_mm_(b); });
  ActiveCentres active;
  for (int i : active_) {  // deepest first: the first probe on free surface gives the answer
    if (calcFreeShare(field, probes_M_.col(i), active) >= 0.5) return excess_mm_(i);
  }
  return 0.0;
}

double ContactResolver::calcFreeShare(const GaussianField& field, const Eigen::Vector3d& p_M,
                                      ActiveCentres& active) const {
  field.findActiveCentres(p_M, active);
  double free = 0.0, all = 0.0;
  for (int q = 0; q < active.size(); ++q) {
    const int k = active.indices[static_cast<size_t>(q)];
    const double w = std::abs(field.getWeights()(k) * active.phi[static_cast<size_t>(q)]);
    all += w;
    if (free_centres_[static_cast<size_t>(k)]) free += w;
  }
  return all > 0.0 ? free / all : 0.0;
}

void ContactResolver::setNormal(int i, const Eigen::Vector3d& gradient) {
  const double g = gradient.norm();
  // A vanishing gradient gives no direction: zero, and calcSubsteps then counts the whole move.
  normal_M_.col(i) = g > 0.0 ? Eigen::Vector3d(gradient / g) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d ContactResolver::calcStartPoint(int i, const Eigen::Matrix3Xd& carried_M) const {
  return probes_M_.col(i) + (carried_M.col(i) - carried_prev_M_.col(i));
}

double ContactResolver::measure(const GaussianField& field, bool measure_only) {
  const int P = countProbes(), B = countBones();
  const double travel = settings_.newton_steps * settings_.newton_step_cap_mm;
  const double radius = calcQueryRadius();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  excess_mm_.setConstant(-kInf);
  std::vector<Eigen::Isometry3d> X_BM(static_cast<size_t>(B));
  for (int b = 0; b < B; ++b) X_BM[static_cast<size_t>(b)] = X_MB_prev_[static_cast<size_t>(b)].inverse();
  // Move of probe i in bone b's frame since its last exact query; s is 1-Lipschitz, so
  // s_ref − move ≤ s_ib ≤ s_ref + move (the upper bound only after a query that found the bone).
  const auto move = [&](int i, int b) {
    return (X_BM[static_cast<size_t>(b)] * probes_M_.col(i) - ref_point_B_[static_cast<size_t>(b)].col(i)).norm();
  };
  const auto bound = [&](int i, int b) { return ref_distance_mm_(i, b) - move(i, b); };
  // Measuring only needs no band: a pair whose lower bound is ≥ −a_ib has e_ib ≤ 0 and cannot
  // count. The response keeps the band for its inequality rows (near contact).
  const double band = measure_only ? 0.0 : settings_.query_band_mm;
  const auto threshold = [&](int i, int b) { return -allowance_mm_(i, b) + band; };
  // Stale references first: a pair whose last exact distance cleared the threshold by the
  // probe's reach, and whose bound no longer does only because the probe has moved in the bone
  // frame since, is queried again where the probe now starts (s is 1-Lipschitz, so a reference
  // at an unprojected point bounds the surface point within the reach as well). Most such
  // probes are still clear and need no projection (iliacus, replay of the main job: about 400
  // instead of 780 projections per measuring call).
  for (int b = 0; b < B; ++b) {
    query_index_.clear();
    for (int i = 0; i < P; ++i) {
      const double reach = travel + slack_mm_(i);
      if (bound(i, b) - reach < threshold(i, b) && ref_distance_mm_(i, b) - reach >= threshold(i, b))
        query_index_.push_back(i);
    }
    if (!query_index_.empty()) queryReferences(b, query_index_, radius, X_BM[static_cast<size_t>(b)]);
  }
  // A probe is projected when some bone may be within the band of its surface point (which
  // lies within the projection's travel of it). Measuring only, a probe whose every such bone
  // holds it certainly inside (upper bound + travel below −a) is left unprojected: it counts
  // as a contact either way; unsure_mm_ keeps its travel in its bounds until it is projected.
  unsure_mm_.setZero(P);
  project_index_.clear();
  for (int i = 0; i < P; ++i) {
    const double reach = travel + slack_mm_(i);
    bool project = false, inside = false;
    for (int b = 0; b < B && !project; ++b) {
      if (!(bound(i, b) - reach < threshold(i, b))) continue;
      if (measure_only && ref_upper_mm_(i, b) + move(i, b) + reach < -allowance_mm_(i, b))
        inside = true;
      else
        project = true;
    }
    if (project)
      project_index_.push_back(i);
    else if (inside)
      unsure_mm_(i) = reach;
  }
  const auto projectProbe = [&](int i) {
    Eigen::Vector3d p = probes_M_.col(i), g;
    projectOntoSurface(field, p, countNewtonSteps(i), settings_.newton_step_cap_mm, settings_.projection_tolerance_mm, &g);
    probes_M_.col(i) = p;
    setNormal(i, g);
    slack_mm_(i) = 0.0;
    unsure_mm_(i) = 0.0;
  };
  const int count = static_cast<int>(project_index_.size());
  projectListed(field);
  report_.projections += count;
  double worst = 0.0;
  // Exact query of the listed probes against bone b; updates the references and excess_.
  const auto queryBone = [&](int b, const std::vector<int>& probes) {
    queryReferences(b, probes, radius, X_BM[static_cast<size_t>(b)]);
    for (size_t k = 0; k < probes.size(); ++k) {
      const int i = probes[k];
      const ContactQueryResult& q = query_out_[k];
      const double e = -ref_distance_mm_(i, b) - allowance_mm_(i, b);
      if (e > excess_mm_(i)) {
        excess_mm_(i) = e;
        exit_normal_M_.col(i) = q.bone < 0 ? Eigen::Vector3d::Zero() : q.normal_W;
      }
      worst = std::max(worst, e);
    }
  };
  deferred_.clear();
  for (int b = 0; b < B; ++b) {
    query_index_.clear();
    for (int i = 0; i < P; ++i) {
      if (!(bound(i, b) - unsure_mm_(i) < threshold(i, b))) continue;
      // Measuring only: a pair certainly inside (upper bound below −a) counts as a contact
      // without a query; its exact depth is needed only if it may be the deepest (below).
      if (measure_only && ref_upper_mm_(i, b) + move(i, b) + unsure_mm_(i) < -allowance_mm_(i, b))
        deferred_.push_back({i, b});
      else
        query_index_.push_back(i);
    }
    if (!query_index_.empty()) queryBone(b, query_index_);
  }
  if (!measure_only) return worst;
  // Deferred pairs: e_ib ∈ [lo, hi] = [−(s_ref + move) − a, −(s_ref − move) − a], lo > 0.
  // excess_ takes lo (the contact count is exact); the deepest probe, over all probes and over
  // those on free surface, is then found exactly by querying in order of the upper bounds
  // until the best exact depth is at least every remaining upper bound (branch and bound).
  upper_mm_.setConstant(P, -kInf);
  for (int i = 0; i < P; ++i) upper_mm_(i) = excess_mm_(i);
  for (const auto& [i, b] : deferred_) {
    excess_mm_(i) = std::max(excess_mm_(i), -(ref_upper_mm_(i, b) + move(i, b) + unsure_mm_(i)) - allowance_mm_(i, b));
    upper_mm_(i) = std::max(upper_mm_(i), -(bound(i, b) - unsure_mm_(i)) - allowance_mm_(i, b));
  }
  std::vector<std::vector<int>> pending(static_cast<size_t>(P));  // deferred bones per probe
  for (const auto& [i, b] : deferred_) pending[static_cast<size_t>(i)].push_back(b);
  std::vector<int> order;
  for (int i = 0; i < P; ++i)
    if (upper_mm_(i) > 0.0) order.push_back(i);
  const auto lower = [&](int a, int c) { return upper_mm_(a) < upper_mm_(c); };
  std::make_heap(order.begin(), order.end(), lower);
  free_penetration_mm_ = 0.0;
  bool have_worst = false;
  std::vector<int> one(1);
  std::vector<bool> rescued(static_cast<size_t>(P), false);
  double deepest = 0.0;  // the heap holds every probe with a positive bound: its first exact, on-surface one
  ActiveCentres active;
  while (!order.empty()) {
    std::pop_heap(order.begin(), order.end(), lower);
    const int i = order.back();
    order.pop_back();
    if (!pending[static_cast<size_t>(i)].empty()) {  // not exact yet: query, then back in the heap
      one[0] = i;
      if (unsure_mm_(i) > 0.0) {
        projectProbe(i);
        ++report_.projections;
      }
      for (int b : pending[static_cast<size_t>(i)]) queryBone(b, one);
      pending[static_cast<size_t>(i)].clear();
      upper_mm_(i) = excess_mm_(i);
      if (upper_mm_(i) > 0.0) {
        order.push_back(i);
        std::push_heap(order.begin(), order.end(), lower);
      }
      continue;
    }
    // Exact and at least every remaining upper bound: the deepest probe left, if it is on the
    // surface. One whose projection ran out of travel gets one longer projection and exact
    // queries again; if that fails too it is left out (its depth is not the surface's).
    Eigen::Vector3d gradient;
    const double value = calcValueAndGradient(field, probes_M_.col(i), gradient);
    if (!(std::abs(value) <= kOnSurfaceMm * gradient.norm())) {
      if (!rescued[static_cast<size_t>(i)]) {
        rescued[static_cast<size_t>(i)] = true;
        Eigen::Vector3d p = probes_M_.col(i), g;
        projectOntoSurface(field, p, kRescueSteps, settings_.newton_step_cap_mm, settings_.projection_tolerance_mm, &g);
        probes_M_.col(i) = p;
        setNormal(i, g);
        ++report_.projections;
        one[0] = i;
        excess_mm_(i) = -kInf;
        for (int b = 0; b < B; ++b)
          if (std::isfinite(allowance_mm_(i, b))) queryBone(b, one);
        upper_mm_(i) = excess_mm_(i);
        if (upper_mm_(i) > 0.0) {
          order.push_back(i);
          std::push_heap(order.begin(), order.end(), lower);
        }
      } else {
        ++report_.probes_off_surface;
      }
      continue;
    }
    if (!have_worst) {
      deepest = excess_mm_(i);
      have_worst = true;
    }
    if (calcFreeShare(field, probes_M_.col(i), active) >= 0.5) {
      free_penetration_mm_ = excess_mm_(i);
      break;
    }
  }
  return deepest;
}

void ContactResolver::projectListed(const GaussianField& field) {
  // The probes to project, grouped by cells of kGroupCellMm: each group collects once the
  // centres that can be active within its probes' travel (LocalFieldEvaluator), which gives
  // the field's own numbers without a grid search per Newton step. Groups collect from their
  // block's list (kGroupsPerBlock³ cells), which collects from all centres: the field is
  // scanned per block instead of per group (iliacus, 2000 centres, ~100 groups in ~15 blocks:
  // collection 0.48 → 0.27 ms per call on one thread; 0.76 ms with a branch per centre).
  cutoff_radius_mm_ = (-std::log(field.getCutoff()) / field.getShapes().array()).sqrt();
  groups_.clear();
  for (int i : project_index_) {
    const Eigen::Array3d cell = (probes_M_.col(i) / kGroupCellMm).array().floor();
    const Eigen::Array3d block = (cell / kGroupsPerBlock).floor();
    groups_.push_back({{static_cast<long long>(block.x()), static_cast<long long>(block.y()),
                        static_cast<long long>(block.z()), static_cast<long long>(cell.x()),
                        static_cast<long long>(cell.y()), static_cast<long long>(cell.z())},
                       i});
  }
  std::sort(groups_.begin(), groups_.end());  // blocks contiguous, and groups within them
  const auto sameBlock = [](const GroupKey& a, const GroupKey& b) { return std::equal(a.begin(), a.begin() + 3, b.begin()); };
  std::vector<size_t> group_start;  // first slot of each group
  std::vector<int> block_start;     // first group of each block
  for (size_t k = 0; k < groups_.size(); ++k) {
    if (k > 0 && groups_[k].first == groups_[k - 1].first) continue;
    if (k == 0 || !sameBlock(groups_[k].first, groups_[k - 1].first)) block_start.push_back(static_cast<int>(group_start.size()));
    group_start.push_back(k);
  }
  group_start.push_back(groups_.size());
  const int group_count = static_cast<int>(group_start.size()) - 1, block_count = static_cast<int>(block_start.size());
  block_start.push_back(group_count);
  // Each group's ball: its probes' mean and the farthest probe plus its travel (steps × cap).
  Eigen::Matrix3Xd group_centre(3, group_count);
  Eigen::VectorXd group_radius(group_count);
  for (int g = 0; g < group_count; ++g) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (size_t k = group_start[static_cast<size_t>(g)]; k < group_start[static_cast<size_t>(g) + 1]; ++k)
      c += probes_M_.col(groups_[k].second);
    c /= static_cast<double>(group_start[static_cast<size_t>(g) + 1] - group_start[static_cast<size_t>(g)]);
    double radius = 0.0;
    for (size_t k = group_start[static_cast<size_t>(g)]; k < group_start[static_cast<size_t>(g) + 1]; ++k) {
      const int i = groups_[k].second;
      radius = std::max(radius, (probes_M_.col(i) - c).norm() + countNewtonSteps(i) * settings_.newton_step_cap_mm);
    }
    group_centre.col(g) = c;
    group_radius(g) = radius;
  }
  std::vector<LocalFieldEvaluator> blocks(static_cast<size_t>(block_count));
#pragma omp parallel for schedule(dynamic, 1)
  for (int b = 0; b < block_count; ++b) {  // a ball holding its groups' balls
    const int first = block_start[static_cast<size_t>(b)], last = block_start[static_cast<size_t>(b) + 1];
    const Eigen::Vector3d c = group_centre.middleCols(first, last - first).rowwise().mean();
    double radius = 0.0;
    for (int g = first; g < last; ++g) radius = std::max(radius, (group_centre.col(g) - c).norm() + group_radius(g));
    blocks[static_cast<size_t>(b)].collect(field, cutoff_radius_mm_, c, radius * (1.0 + 1e-9) + 1e-9);
  }
  std::vector<int> block_of_group(static_cast<size_t>(group_count));
  for (int b = 0; b < block_count; ++b)
    for (int g = block_start[static_cast<size_t>(b)]; g < block_start[static_cast<size_t>(b) + 1]; ++g)
      block_of_group[static_cast<size_t>(g)] = b;
#pragma omp parallel for schedule(dynamic, 4)
  for (int g = 0; g < group_count; ++g) {  // independent per probe: results do not depend on the threads
    LocalFieldEvaluator evaluate;
    evaluate.collect(field, cutoff_radius_mm_, group_centre.col(g), group_radius(g),
                     &blocks[static_cast<size_t>(block_of_group[static_cast<size_t>(g)])].getCandidates());
    for (size_t k = group_start[static_cast<size_t>(g)]; k < group_start[static_cast<size_t>(g) + 1]; ++k) {
      const int i = groups_[k].second;
      Eigen::Vector3d p = probes_M_.col(i), gradient;
      projectOntoSurfaceWith(evaluate, p, countNewtonSteps(i), settings_.newton_step_cap_mm, settings_.projection_tolerance_mm,
                             &gradient);
      probes_M_.col(i) = p;
      setNormal(i, gradient);
      slack_mm_(i) = 0.0;
    }
  }
}

double ContactResolver::calcQueryRadius() const {
  return settings_.query_band_mm + settings_.newton_steps * settings_.newton_step_cap_mm + kLowerBoundReachMm;
}

double ContactResolver::calcLowerBound(int i, int b, const Eigen::Vector3d& p_B) const {
  return ref_distance_mm_(i, b) - (p_B - ref_point_B_[static_cast<size_t>(b)].col(i)).norm();
}

int ContactResolver::countNewtonSteps(int i) const {
  return settings_.newton_steps + static_cast<int>(std::ceil(slack_mm_(i) / settings_.newton_step_cap_mm));
}

void ContactResolver::queryReferences(int b, const std::vector<int>& probes, double radius_mm,
                                      const Eigen::Isometry3d& X_BM) {
  query_points_.resize(3, static_cast<Eigen::Index>(probes.size()));
  for (size_t k = 0; k < probes.size(); ++k) query_points_.col(static_cast<Eigen::Index>(k)) = probes_M_.col(probes[k]);
  bone_sets_[static_cast<size_t>(b)].queryProbes(query_points_, radius_mm, query_out_);
  report_.probe_queries += static_cast<long long>(probes.size());
  for (size_t k = 0; k < probes.size(); ++k) {
    const int i = probes[k];
    const ContactQueryResult& q = query_out_[k];
    const double s = q.bone < 0 ? radius_mm : q.signed_distance_mm;
    ref_distance_mm_(i, b) = s;
    ref_upper_mm_(i, b) = q.bone < 0 ? std::numeric_limits<double>::infinity() : s;
    ref_point_B_[static_cast<size_t>(b)].col(i) = X_BM * probes_M_.col(i);
  }
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

void ContactResolver::watchBoneVertices(const GaussianField& field) {
  const int P = countProbes(), B = countBones();
  // Only bone vertices within kWatchReachMm of a probe that may be that near the bone can be
  // inside the muscle (unless a penetration is deeper than that and the muscle twice as thick).
  inside_.clear();
  for (int b = 0; b < B; ++b) {
    const Eigen::Isometry3d X_BM = X_MB_prev_[static_cast<size_t>(b)].inverse();
    query_points_.resize(3, P);
    int n = 0;
    for (int i = 0; i < P; ++i) {
      const Eigen::Vector3d p_B = X_BM * probes_M_.col(i);
      if (calcLowerBound(i, b, p_B) <= kWatchReachMm) query_points_.col(n++) = p_B;
    }
    watch_.findInside(b, X_MB_prev_[static_cast<size_t>(b)], field, query_points_.leftCols(n), kWatchReachMm, inside_);
  }
  if (inside_.empty()) return;
  // Deepest first: f grows into the muscle, so a larger value is (about) a deeper vertex.
  std::stable_sort(inside_.begin(), inside_.end(),
                   [](const BoneVertexInside& a, const BoneVertexInside& b) { return a.value > b.value; });
  const double cover2 = settings_.cover_radius_mm * settings_.cover_radius_mm;
  const SpatialGrid probe_grid(probes_M_, settings_.cover_radius_mm);
  std::vector<int> near;
  std::vector<bool> taken(static_cast<size_t>(P), false);
  std::vector<Eigen::Vector3d> seats;
  std::vector<std::vector<int>> seated(static_cast<size_t>(B));
  struct Found {
    double depth_mm;  ///< along the vertex's inward normal: ≥ the point's depth in the bone
    int bone;
    Eigen::Vector3d point_M;
  };
  std::vector<Found> found;
  ActiveCentres active;
  for (const BoneVertexInside& hit : inside_) {
    const int b = hit.bone;
    const auto watches = [&](int j) { return std::isfinite(allowance_mm_(j, b)); };
    const double depth = marchToSurface(field, hit.vertex_M, hit.inward_M, kSeatStepMm, kSeatDepthMm);
    if (depth >= kSeatDepthMm) continue;  // no surface found below: not a penetration to seat at
    // Judged at the surface point below the vertex (a probe near the vertex itself may lie
    // where the surfaces cross, and see no depth), among the probes before this call's moves:
    // in the rest overlap (left alone, as the allowances do) when the nearest probe is one
    // excluded for the bone; covered by a near probe that watches the bone and already
    // measured about this depth (else that probe moves to the seat).
    const Eigen::Vector3d seat = hit.vertex_M + depth * hit.inward_M;
    probe_grid.findWithinRadius(seat, kOverlapReach * settings_.cover_radius_mm, near);
    int closest = -1, near_watching = -1;
    double closest2 = std::numeric_limits<double>::infinity(), watching2 = closest2;
    bool covered = false;
    for (int j : near) {
      if (taken[static_cast<size_t>(j)]) continue;
      const double d2 = (probes_M_.col(j) - seat).squaredNorm();
      if (d2 < closest2) {
        closest2 = d2;
        closest = j;
      }
      if (!watches(j) || d2 > cover2) continue;
      covered = covered || -ref_distance_mm_(j, b) >= depth - 0.5 * settings_.tolerance_mm;
      if (d2 < watching2) {
        watching2 = d2;
        near_watching = j;
      }
    }
    if (closest >= 0 && !watches(closest)) continue;
    found.push_back({depth, b, seat});
    if (settings_.max_reseats == 0 || !(depth > settings_.tolerance_mm) || covered) continue;
    for (const Eigen::Vector3d& v : seats) covered = covered || (v - seat).squaredNorm() <= cover2;
    if (covered) continue;
    const double share = calcFreeShare(field, seat, active);
    if (share < 0.5) continue;  // attached surface: a push cannot move it
    // A near probe that saw less moves to the seat; else the nearest probe watching the bone
    // and not in contact leaves its place.
    int nearest = near_watching;
    double best = std::numeric_limits<double>::infinity();
    for (int j = 0; j < P && near_watching < 0; ++j) {
      if (taken[static_cast<size_t>(j)] || !watches(j) || excess_mm_(j) > 0.0) continue;
      const double d2 = (probes_M_.col(j) - seat).squaredNorm();
      if (d2 < best) {
        best = d2;
        nearest = j;
      }
    }
    if (report_.probes_reseated >= settings_.max_reseats || nearest < 0) {
      ++report_.uncovered_left;
      continue;
    }
    taken[static_cast<size_t>(nearest)] = true;
    seats.push_back(seat);
    probes_M_.col(nearest) = seat;
    Eigen::Vector3d gradient;
    calcValueAndGradient(field, seat, gradient);
    setNormal(nearest, gradient);
    slack_mm_(nearest) = 0.0;
    free_share_(nearest) = share;
    thickness_mm_(nearest) = calcLocalThickness(field, seat, settings_.thickness_step_mm, settings_.thickness_max_mm);
    for (int c = 0; c < B; ++c)
      if (std::isfinite(allowance_mm_(nearest, c))) seated[static_cast<size_t>(c)].push_back(nearest);
    ++report_.probes_reseated;
  }
  // Their references are where they now are.
  const double radius = calcQueryRadius();
  for (int c = 0; c < B; ++c)
    if (!seated[static_cast<size_t>(c)].empty())
      queryReferences(c, seated[static_cast<size_t>(c)], radius, X_MB_prev_[static_cast<size_t>(c)].inverse());
  // The deepest of the points found, exactly: |s| ≤ the depth along the normal (the vertex is on
  // the bone), so in order of that depth until it is no more than the best exact depth.
  std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.depth_mm > b.depth_mm; });
  std::vector<ContactQueryResult> answer;
  query_points_.resize(3, 1);
  for (const Found& f : found) {
    if (f.depth_mm <= report_.max_penetration_watched_mm) break;
    query_points_.col(0) = f.point_M;
    bone_sets_[static_cast<size_t>(f.bone)].queryProbes(query_points_, f.depth_mm + 1.0, answer);
    ++report_.probe_queries;
    if (answer[0].bone >= 0)
      report_.max_penetration_watched_mm = std::max(report_.max_penetration_watched_mm, -answer[0].signed_distance_mm);
  }
}

bool ContactResolver::respondOnce(GaussianField& field, double step_limit_mm) {
  // The excess depth the push aims at, and the active probes (deeper than both it and their
  // allowance), deepest first.
  const double aim_mm = settings_.tolerance_mm - settings_.aim_below_tolerance_mm;
  const double active_above_mm = std::max(0.0, aim_mm);
  active_.clear();
  for (int i = 0; i < countProbes(); ++i)
    if (excess_mm_(i) > active_above_mm && exit_normal_M_.col(i).squaredNorm() > 0.0) active_.push_back(i);
  if (active_.empty()) return false;
  std::sort(active_.begin(), active_.end(), [&](int a, int b) { return excess_mm_(a) > excess_mm_(b); });
  // Length L of the push: block_fraction of the local rest thickness (median over the active
  // probes), so the push moves the muscle's cross-section as a block instead of denting its
  // surface (a dent changes the curvature, which the next descent would undo).
  std::vector<double> t;
  t.reserve(active_.size());
  for (int i : active_) t.push_back(thickness_mm_(i));
  std::nth_element(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(t.size() / 2), t.end());
  const double L = std::max(settings_.block_fraction * t[t.size() / 2], settings_.thickness_step_mm);
  // One row per cluster: a probe is kept unless a deeper kept probe lies within L/2 (the
  // smooth push moves its neighbours about as far).
  rows_.clear();
  for (int i : active_) {
    bool near = false;
    for (int j : rows_) near = near || (probes_M_.col(i) - probes_M_.col(j)).squaredNorm() < 0.25 * L * L;
    if (!near) rows_.push_back(i);
  }
  const Eigen::Matrix3Xd& xi = field.getCentres();
  const Eigen::VectorXd& lambda = field.getWeights();
  const Eigen::VectorXd& alpha = field.getShapes();
  // Centre k moves by u_k = Σ_b ψ_k(p_b) γ_b n_b over the rows b, ψ_k(p) = exp(−|ξ_k − p|²/(L² + 1/α_k)):
  // the push covers the centre's own footprint (width 1/√α_k), so the centres that make the
  // surface near a row move together. A probe moves by the mean move v(p) of the centres
  // active at p, weighted by |λ_k φ_k(p)| (a translated muscle carries its probes exactly),
  // and the surface along its unit gradient ĝ by t = −Δf(p)/‖∇f(p)‖, to first order
  // Δf(p) = Σ_k ∂f(p)/∂ξ_k · u_k. The probe's signed distance to its bone then grows by
  //   Δs_a = n_a·(v − (ĝ·v) ĝ) + c_a t_a,  c_a = ĝ_a·n_a,
  // linear in γ: Δs_a = A_a γ. Rows ask Δs_a = e_a − aim, solved in the damped
  // least-squares sense (AᵀA + μ tr(AᵀA)/m I) γ = Aᵀ(e − aim).
  ActiveCentres active;
  Eigen::VectorXd carry;
  // ψ_k(p_b) of every free centre (0 beyond 3 widths), one column per row, made as rows join.
  const int N = field.getNumCentres();
  const auto addKernelColumns = [&](int from) {
    const int m = static_cast<int>(rows_.size());
    psi_.conservativeResize(N, m);
    for (int b = from; b < m; ++b) {
      const Eigen::Vector3d pb = probes_M_.col(rows_[static_cast<size_t>(b)]);
      for (int k = 0; k < N; ++k) {
        const double width2 = L * L + 1.0 / alpha(k);
        const double r2 = (xi.col(k) - pb).squaredNorm();
        psi_(k, b) = free_centres_[static_cast<size_t>(k)] && r2 <= 9.0 * width2 ? std::exp(-r2 / width2) : 0.0;
      }
    }
  };
  psi_.resize(N, 0);
  addKernelColumns(0);
  // Fills `out` with A_a for probe i against the current rows; false when ∇f(p_i) vanishes.
  const auto makeRow = [&](int i, Eigen::Ref<Eigen::RowVectorXd> out) {
    const int m = static_cast<int>(rows_.size());
    const Eigen::Vector3d p = probes_M_.col(i), n = exit_normal_M_.col(i);
    out.setZero();
    field.findActiveCentres(p, active);
    Eigen::Vector3d grad = Eigen::Vector3d::Zero();
    double weight = 0.0;
    for (int q = 0; q < active.size(); ++q) {
      const int k = active.indices[static_cast<size_t>(q)];
      const double w = lambda(k) * active.phi[static_cast<size_t>(q)];
      grad -= 2.0 * alpha(k) * w * (p - xi.col(k));
      weight += std::abs(w);
    }
    const double g = grad.norm();
    if (!(g > 0.0) || !(weight > 0.0)) return false;
    const Eigen::Vector3d gh = grad / g;
    const double c = gh.dot(n);
    carry.setZero(m);
    for (int q = 0; q < active.size(); ++q) {
      const int k = active.indices[static_cast<size_t>(q)];
      if (!free_centres_[static_cast<size_t>(k)]) continue;
      const double w = lambda(k) * active.phi[static_cast<size_t>(q)];
      const Eigen::Vector3d dfdxi = 2.0 * alpha(k) * w * (p - xi.col(k));  // ∂f(p)/∂ξ_k
      for (int b = 0; b < m; ++b) {
        const double psi = psi_(k, b);
        if (psi == 0.0) continue;
        out(b) -= c / g * psi * dfdxi.dot(exit_normal_M_.col(rows_[static_cast<size_t>(b)]));
        carry(b) += std::abs(w) / weight * psi;
      }
    }
    for (int b = 0; b < m; ++b) {
      const Eigen::Vector3d& nb = exit_normal_M_.col(rows_[static_cast<size_t>(b)]);
      out(b) += carry(b) * (n.dot(nb) - c * gh.dot(nb));
    }
    return true;
  };
  // Probes near contact (queried, within query_band_mm of their bone, not active) must not be
  // pushed in: after a solve, those predicted to end deeper than the aim join the rows
  // with their own target (an active-set pass for the inequalities Δs ≥ e − aim).
  const double reach2 = 9.0 * (L * L + 1.0 / alpha.minCoeff());  // no centre within 3 widths of a row: no move
  near_.clear();
  for (int i = 0; i < countProbes(); ++i)
    if (excess_mm_(i) <= active_above_mm && excess_mm_(i) > -settings_.query_band_mm &&
        exit_normal_M_.col(i).squaredNorm() > 0.0)
      near_.push_back(i);
  constexpr int kActiveSetPasses = 3;
  Eigen::VectorXd gamma;
  Eigen::MatrixXd A;
  Eigen::RowVectorXd candidate_row, row_buffer;
  for (int pass = 0;; ++pass) {
    const int m = static_cast<int>(rows_.size());
    A.setZero(m, m);
    Eigen::VectorXd delta(m);
    for (int a = 0; a < m; ++a) {
      const int i = rows_[static_cast<size_t>(a)];
      delta(a) = excess_mm_(i) - aim_mm;
      row_buffer.resize(m);
      if (makeRow(i, row_buffer)) A.row(a) = row_buffer;
    }
    Eigen::MatrixXd G = A.transpose() * A;
    G.diagonal().array() += settings_.damping * G.trace() / m + std::numeric_limits<double>::min();
    gamma = G.ldlt().solve(A.transpose() * delta);
    if (!gamma.allFinite()) return false;
    if (pass + 1 >= kActiveSetPasses) break;
    std::vector<int> added;
    candidate_row.resize(m);
    for (int i : near_) {
      if (std::find(rows_.begin(), rows_.end(), i) != rows_.end()) continue;
      bool covered = false;
      for (int j : added) covered = covered || (probes_M_.col(i) - probes_M_.col(j)).squaredNorm() < 0.25 * L * L;
      bool reached = false;
      for (int b = 0; b < m && !reached; ++b)
        reached = (probes_M_.col(i) - probes_M_.col(rows_[static_cast<size_t>(b)])).squaredNorm() <= reach2;
      if (covered || !reached || !makeRow(i, candidate_row)) continue;
      if (candidate_row.dot(gamma) < excess_mm_(i) - aim_mm) added.push_back(i);
    }
    if (added.empty()) break;
    const int from = static_cast<int>(rows_.size());
    rows_.insert(rows_.end(), added.begin(), added.end());
    addKernelColumns(from);
  }
  const int m = static_cast<int>(rows_.size());
  Eigen::Matrix3Xd moved_centres = xi;
  std::vector<int> centres;
  double longest = 0.0;
  for (int k = 0; k < N; ++k) {
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    bool any = false;
    for (int b = 0; b < m; ++b) {
      if (psi_(k, b) == 0.0) continue;
      u += psi_(k, b) * gamma(b) * exit_normal_M_.col(rows_[static_cast<size_t>(b)]);
      any = true;
    }
    if (!any) continue;
    moved_centres.col(k) += u;
    centres.push_back(k);
    longest = std::max(longest, u.norm());
  }
  if (centres.empty() || !(longest > 0.0)) return false;
  // Trust region: no centre moves more than step_limit_mm (the linearisation holds there).
  const double scale = longest > step_limit_mm ? step_limit_mm / longest : 1.0;
  for (int k : centres) moved_centres.col(k) = xi.col(k) + scale * (moved_centres.col(k) - xi.col(k));
  // The probes near the push follow it (v(p) above); the next measurement projects them onto
  // the new surface.
  // Only probes measured last time (near a bone) are carried; the others are projected from
  // where they are when they come near (their slack covers the move).
  for (int i = 0; i < countProbes(); ++i) {
    if (!(excess_mm_(i) > -std::numeric_limits<double>::infinity())) continue;
    bool near = false;
    for (int b = 0; b < m && !near; ++b)
      near = (probes_M_.col(i) - probes_M_.col(rows_[static_cast<size_t>(b)])).squaredNorm() <= reach2;
    if (!near) continue;
    field.findActiveCentres(probes_M_.col(i), active);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double weight = 0.0;
    for (int q = 0; q < active.size(); ++q) {
      const int k = active.indices[static_cast<size_t>(q)];
      const double w = std::abs(lambda(k)) * active.phi[static_cast<size_t>(q)];
      sum += w * (moved_centres.col(k) - xi.col(k));
      weight += w;
    }
    if (weight > 0.0) probes_M_.col(i) += sum / weight;
  }
  const Eigen::Matrix3Xd old_centres = xi;
  for (int k : centres) moved_[static_cast<size_t>(k)] = true;
  field.setCentrePositions(moved_centres);
  addSlack(field, centres, old_centres, scale * longest);
  last_step_mm_ = scale * longest;
  return true;
}

}  // namespace rbfmuscle
