// The island and cavity guard on fields whose pieces are known in closed form.
#include "dynamics/topology_guard.h"

#include "geometry/iso_surface.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_measures.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rbfmuscle {
namespace {

const Eigen::AlignedBox3d kBox(Eigen::Vector3d::Constant(-40.0), Eigen::Vector3d::Constant(40.0));
constexpr double kCell = 2.0;
const Eigen::Vector2d kLimits(100.0, 100.0);  ///< |λ| limits of both centres

TriangleMesh extract(const GaussianField& field) {
  return extractIsoSurface([&field](const Eigen::Matrix3Xd& p, Eigen::VectorXd& v) { field.calcValues(p, v); }, kBox,
                           kCell);
}

/// Body: one Gaussian with f = 0 on the sphere of radius 10 mm (λ e^{−0.01·100} = 5 = −b).
/// Second centre: `lambda2` with α = `alpha2` (mm⁻²) at `x2`.
GaussianField makeBodyAnd(double lambda2, const Eigen::Vector3d& x2, double alpha2 = 0.5) {
  Eigen::Matrix3Xd xi(3, 2);
  xi.col(0).setZero();
  xi.col(1) = x2;
  return GaussianField(-5.0, xi, Eigen::Vector2d(5.0 * std::exp(1.0), lambda2), Eigen::Vector2d(0.01, alpha2));
}

TEST(TopologyGuard, LowersAnIslandAndLeavesTheBody) {
  // A narrow bump 30 mm from the body: peak 10 − 5 > 0, a separate piece of radius ~1.2 mm.
  GaussianField field = makeBodyAnd(10.0, Eigen::Vector3d(30.0, 0.0, 0.0));
  ASSERT_EQ(checkMesh(extract(field)).components, 2);
  const double body_volume = calcVolume(extract(makeBodyAnd(0.0, Eigen::Vector3d::Zero())));
  TopologyGuard guard({true, true}, kLimits, TopologySettings{});
  const TopologyReport r = guard.run(field, kBox);
  EXPECT_EQ(r.islands_found, 1);
  EXPECT_EQ(r.islands_removed, 1);  // a crumb of a node or two, below bridge_nodes
  EXPECT_EQ(r.cavities_found, 0);
  EXPECT_EQ(r.defects_left, 0);
  EXPECT_EQ(r.stop_reason, TopologyStop::kOnePiece) << toString(r.stop_reason);
  EXPECT_GT(r.weights_changed, 0);
  EXPECT_LT(field.getWeights()(1), 5.0);  // the bump no longer reaches zero on its own
  EXPECT_NEAR(field.getWeights()(0), 5.0 * std::exp(1.0), 1e-2);  // the body barely changes
  const TriangleMesh after = extract(field);
  EXPECT_EQ(checkMesh(after).components, 1);
  EXPECT_NEAR(calcVolume(after), body_volume, 1e-3 * body_volume);
  EXPECT_EQ(guard.countPieces(field, kBox), 1);
}

TEST(TopologyGuard, JoinsAPieceOfMuscleBackInsteadOfRemovingIt) {
  // Two spheres of radius ~10 mm, centres 30 mm apart: f(0) = 2·13.6·e^{−2.25} − 5 < 0.
  Eigen::Matrix3Xd xi(3, 2);
  xi << -15.0, 15.0, 0.0, 0.0, 0.0, 0.0;
  const double lambda = 5.0 * std::exp(1.0);
  GaussianField field(-5.0, xi, Eigen::Vector2d(lambda, lambda), Eigen::Vector2d(0.01, 0.01));
  ASSERT_EQ(checkMesh(extract(field)).components, 2);
  TopologyGuard guard({true, true}, Eigen::Vector2d(3.0 * lambda, 3.0 * lambda), TopologySettings{});
  const TopologyReport r = guard.run(field, kBox);
  EXPECT_EQ(r.islands_found, 1);
  EXPECT_GT(r.islands_bridged, 0);
  EXPECT_EQ(r.islands_removed, 0);
  EXPECT_EQ(r.stop_reason, TopologyStop::kOnePiece) << toString(r.stop_reason);
  EXPECT_EQ(checkMesh(extract(field)).components, 1);
  EXPECT_GT(field.calcValue(Eigen::Vector3d(-15.0, 0.0, 0.0)), 0.0);  // both pieces kept
  EXPECT_GT(field.calcValue(Eigen::Vector3d(15.0, 0.0, 0.0)), 0.0);
  EXPECT_GT(field.calcValue(Eigen::Vector3d::Zero()), 0.0);             // joined in between
}

TEST(TopologyGuard, JoinsACrumbAcrossAShallowDipWhereRemovingItWouldSinkAFlatBody) {
  // A flat body, f = λ e^{−0.001 r²} − 5 (f = 0 at r = 9 mm, 0.42 at its centre), and a narrow
  // bump on the node (12, 0, 0): f there −0.305 + 0.5 = 0.195, a one-node crumb; the node
  // (10, 0, 0) between it and the body has f = −0.094. Joining (+0.094 + 0.05 there) is the
  // smaller change than removing (−0.195 − 0.25), which the flat body shares.
  Eigen::Matrix3Xd xi(3, 2);
  xi << 0.0, 12.0, 0.0, 0.0, 0.0, 0.0;
  const GaussianField sheet(-5.0, xi, Eigen::Vector2d(5.0 * std::exp(0.081), 0.5), Eigen::Vector2d(0.001, 2.0));
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero(), crumb(12.0, 0.0, 0.0), dip(10.0, 0.0, 0.0);
  ASSERT_NEAR(sheet.calcValue(crumb), 0.195, 1e-3);
  ASSERT_NEAR(sheet.calcValue(dip), -0.094, 1e-3);
  ASSERT_EQ(checkMesh(extract(sheet)).components, 2);

  GaussianField joined = sheet;
  const TopologyReport r = TopologyGuard({true, true}, kLimits, TopologySettings{}).run(joined, kBox);
  EXPECT_EQ(r.islands_found, 1);
  EXPECT_EQ(r.islands_bridged, 1);
  EXPECT_EQ(r.islands_removed, 0);
  EXPECT_EQ(r.stop_reason, TopologyStop::kOnePiece) << toString(r.stop_reason);
  EXPECT_EQ(checkMesh(extract(joined)).components, 1);
  EXPECT_GT(joined.calcValue(crumb), 0.0);  // kept
  EXPECT_NEAR(joined.calcValue(dip), TopologySettings{}.crumb_join_level, 0.01);  // raised just above zero

  TopologySettings never;
  never.crumb_join_level = 0.0;
  GaussianField removed = sheet;
  const TopologyReport off = TopologyGuard({true, true}, kLimits, never).run(removed, kBox);
  EXPECT_EQ(off.islands_bridged, 0);
  EXPECT_EQ(off.islands_removed, 1);
  EXPECT_LT(removed.calcValue(crumb), 0.0);
  // Removing moves the body's f three times as far as joining does (−0.46 against +0.16).
  const double body_before = sheet.calcValue(centre);
  EXPECT_GT(std::abs(removed.calcValue(centre) - body_before), 2.0 * std::abs(joined.calcValue(centre) - body_before));
}

TEST(TopologyGuard, RaisesAThinningNeckBeforeItIsCut) {
  // Two spheres of radius ~10 mm, centres 2d apart: f(0) = 2λ e^{−0.01 d²} − 5 = 0.1 on the
  // node at the origin, the neck's thinnest point, so {f > 0} is one piece but {f > 0.2} two.
  const double lambda = 5.0 * std::exp(1.0);
  const double d = std::sqrt(-100.0 * std::log(5.1 / (2.0 * lambda)));
  Eigen::Matrix3Xd xi(3, 2);
  xi << -d, d, 0.0, 0.0, 0.0, 0.0;
  const GaussianField dumbbell(-5.0, xi, Eigen::Vector2d(lambda, lambda), Eigen::Vector2d(0.01, 0.01));
  ASSERT_NEAR(dumbbell.calcValue(Eigen::Vector3d::Zero()), 0.1, 1e-12);
  ASSERT_EQ(checkMesh(extract(dumbbell)).components, 1);
  const Eigen::Vector2d limits(3.0 * lambda, 3.0 * lambda);

  GaussianField field = dumbbell;
  TopologyGuard guard({true, true}, limits, TopologySettings{});
  const TopologyReport r = guard.run(field, kBox);
  EXPECT_EQ(r.islands_found, 0);
  EXPECT_EQ(r.necks_raised, 1);
  EXPECT_EQ(r.stop_reason, TopologyStop::kOnePiece) << toString(r.stop_reason);
  // Raised to 1.5 × 0.2 at the node, symmetrically, by weights that keep their sign.
  EXPECT_NEAR(field.calcValue(Eigen::Vector3d::Zero()), 0.3, 1e-9);
  EXPECT_NEAR(field.getWeights()(0), field.getWeights()(1), 1e-12);
  EXPECT_GT(field.getWeights()(0), lambda);
  EXPECT_EQ(checkMesh(extract(field)).components, 1);
  // A second look finds the neck above the level and leaves the field alone.
  const Eigen::VectorXd raised = field.getWeights();
  EXPECT_EQ(guard.run(field, kBox).weights_changed, 0);
  EXPECT_EQ(field.getWeights(), raised);

  TopologySettings off;
  off.neck_level = 0.0;
  GaussianField untouched = dumbbell;
  TopologyGuard without({true, true}, limits, off);
  EXPECT_EQ(without.run(untouched, kBox).weights_changed, 0);
  EXPECT_EQ(untouched.getWeights(), dumbbell.getWeights());
}

TEST(TopologyGuard, FillsACavity) {
  // A negative Gaussian 2 mm from the body's centre (on a grid node): f there ≈ 13.1 − 5 − 10
  // < 0, a bubble of radius ~1.7 mm.
  GaussianField field = makeBodyAnd(-10.0, Eigen::Vector3d(2.0, 0.0, 0.0), 0.1);
  ASSERT_LT(field.calcValue(Eigen::Vector3d(2.0, 0.0, 0.0)), 0.0);
  ASSERT_EQ(checkMesh(extract(field)).components, 2);
  TopologyGuard guard({true, true}, kLimits, TopologySettings{});
  const TopologyReport r = guard.run(field, kBox);
  EXPECT_EQ(r.islands_found, 0);
  EXPECT_EQ(r.cavities_found, 1);
  EXPECT_EQ(r.defects_left, 0);
  EXPECT_EQ(r.stop_reason, TopologyStop::kOnePiece) << toString(r.stop_reason);
  EXPECT_LE(field.getWeights()(1), 0.0);  // weights keep their sign
  EXPECT_GT(field.getWeights()(1), -10.0);
  EXPECT_EQ(checkMesh(extract(field)).components, 1);
}

TEST(TopologyGuard, UsesAttachedCentresOnlyWhenNoFreeOneReaches) {
  GaussianField field = makeBodyAnd(10.0, Eigen::Vector3d(30.0, 0.0, 0.0));
  field.setCutoff(1e-3);  // the body centre no longer reaches the bump
  TopologyGuard guard({true, false}, kLimits, TopologySettings{});  // the bump's centre is attached
  const TopologyReport r = guard.run(field, kBox);
  EXPECT_EQ(r.stop_reason, TopologyStop::kOnePiece) << toString(r.stop_reason);
  EXPECT_LT(field.getWeights()(1), 10.0);
  EXPECT_EQ(field.getWeights()(0), 5.0 * std::exp(1.0));
}

TEST(TopologyGuard, OnePieceIsLeftUntouchedAndDisabledDoesNothing) {
  GaussianField field = makeBodyAnd(0.5, Eigen::Vector3d(3.0, 0.0, 0.0));  // one piece
  const Eigen::VectorXd before = field.getWeights();
  TopologyGuard guard({true, true}, kLimits, TopologySettings{});
  const TopologyReport r = guard.run(field, kBox);
  EXPECT_EQ(r.stop_reason, TopologyStop::kOnePiece);
  EXPECT_EQ(r.rounds, 1);
  EXPECT_EQ(r.weights_changed, 0);
  EXPECT_EQ(field.getWeights(), before);
  EXPECT_EQ(r.grid_nodes, 41 * 41 * 41);

  GaussianField island = makeBodyAnd(10.0, Eigen::Vector3d(30.0, 0.0, 0.0));
  TopologySettings off;
  off.enabled = false;
  TopologyGuard disabled({true, true}, kLimits, off);
  EXPECT_EQ(disabled.run(island, kBox).stop_reason, TopologyStop::kDisabled);
  EXPECT_EQ(island.getWeights()(1), 10.0);
}

TEST(TopologyGuard, RejectsBadSettingsAndSizes) {
  TopologySettings s;
  s.cell_mm = 0.0;
  EXPECT_THROW(TopologyGuard({true}, Eigen::VectorXd::Ones(1), s), std::invalid_argument);
  s = TopologySettings{};
  s.max_rounds = 0;
  EXPECT_THROW(TopologyGuard({true}, Eigen::VectorXd::Ones(1), s), std::invalid_argument);
  s = TopologySettings{};
  s.bridge_nodes = 0;
  EXPECT_THROW(TopologyGuard({true}, Eigen::VectorXd::Ones(1), s), std::invalid_argument);
  s = TopologySettings{};
  s.margin = -1.0;
  EXPECT_THROW(TopologyGuard({true}, Eigen::VectorXd::Ones(1), s), std::invalid_argument);
  s = TopologySettings{};
  s.neck_level = -0.1;
  EXPECT_THROW(TopologyGuard({true}, Eigen::VectorXd::Ones(1), s), std::invalid_argument);
  s = TopologySettings{};
  s.crumb_join_level = -0.05;
  EXPECT_THROW(TopologyGuard({true}, Eigen::VectorXd::Ones(1), s), std::invalid_argument);
  GaussianField field = makeBodyAnd(1.0, Eigen::Vector3d::Zero());
  TopologyGuard guard({true}, Eigen::VectorXd::Ones(1), TopologySettings{});
  EXPECT_THROW(guard.run(field, kBox), std::invalid_argument);  // two centres, a mask of one
  EXPECT_THROW(TopologyGuard({true, true}, Eigen::VectorXd::Ones(1), TopologySettings{}), std::invalid_argument);
  EXPECT_THROW(TopologyGuard({true}, -Eigen::VectorXd::Ones(1), TopologySettings{}), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
