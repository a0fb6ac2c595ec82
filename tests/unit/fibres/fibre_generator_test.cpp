// SPDX-License-Identifier: Apache-2.0
#include "fibres/fibre_generator.h"
#include "fibres/interior_grid.h"

#include "fibre_test_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace rbfmuscle {
namespace {

class RodFibres : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    field_ = new GaussianField(test::makeFibreRod());
    fibres_ = new RestFibres(generateFibres(*field_, test::rodOrigin(), test::rodInsertion(),
                                            test::makeSmallFibreSettings()));
  }
  static void TearDownTestSuite() {
    delete fibres_;
    delete field_;
  }
  static GaussianField* field_;
  static RestFibres* fibres_;
};
GaussianField* RodFibres::field_ = nullptr;
RestFibres* RodFibres::fibres_ = nullptr;

TEST_F(RodFibres, EveryPointIsInsideWithTheMargin) {
  const RestFibres& f = *fibres_;
  ASSERT_EQ(f.points_mm.cols(), 30 * 11);
  Eigen::VectorXd values;
  field_->calcValues(f.points_mm, values);
  EXPECT_GT(values.minCoeff(), 0.0);
  EXPECT_EQ(f.points_below_margin, 0) << "min f " << f.min_value;
  EXPECT_DOUBLE_EQ(f.min_value, values.minCoeff());
}

TEST_F(RodFibres, RunFromOriginToInsertion) {
  const RestFibres& f = *fibres_;
  Eigen::VectorXd inside;  // each fibre's length without its tendons
  calcFibreLengths(f.points_mm, 10, inside);
  for (int i = 0; i < f.count; ++i) {
    const Eigen::Vector3d a = f.points_mm.col(i * 11), b = f.points_mm.col(i * 11 + 10);
    EXPECT_LE((a - test::rodOrigin().col(0)).norm(), f.attachment_radius_origin_mm + f.end_climb_max_mm + 1e-9) << i;
    EXPECT_LE((b - test::rodInsertion().col(0)).norm(), f.attachment_radius_insertion_mm + f.end_climb_max_mm + 1e-9) << i;
    // x increases along each fibre (the rod is straight), lengths at least the chord.
    for (int j = 0; j < 10; ++j) EXPECT_LT(f.points_mm(0, i * 11 + j), f.points_mm(0, i * 11 + j + 1)) << i << " " << j;
    EXPECT_GE(inside(i), (b - a).norm() - 1e-9);
    EXPECT_LE(inside(i), 1.1 * (b - a).norm()) << "fibre " << i << " wanders";
    // Tendons from the areas' points (one each here) to the ends count in the length.
    EXPECT_EQ(f.attachments_mm.col(2 * i), test::rodOrigin().col(0)) << i;
    EXPECT_EQ(f.attachments_mm.col(2 * i + 1), test::rodInsertion().col(0)) << i;
    EXPECT_NEAR(f.lengths_mm(i), (a - test::rodOrigin().col(0)).norm() + inside(i) +
                                     (test::rodInsertion().col(0) - b).norm(), 1e-9) << i;
  }
}

TEST(FibreGenerator, EachFibreIsAttachedToTheAreaPointsNearestItsEnds) {
  const GaussianField field = test::makeFibreRod();
  // Areas of several points around each end of the rod, some beyond its surface.
  Eigen::Matrix3Xd origin(3, 4), insertion(3, 3);
  origin << -32, -33, -32, -36, 0, 5, -6, 0, 0, 1, 2, -4;
  insertion << 32, 34, 31, 4, -3, 0, 0, 3, -5;
  const RestFibres f = generateFibres(field, origin, insertion, test::makeSmallFibreSettings());
  ASSERT_EQ(f.attachments_mm.cols(), 2 * f.count);
  const int per = f.segments + 1;
  const auto nearest = [](const Eigen::Matrix3Xd& area, const Eigen::Vector3d& p) {
    Eigen::Index k = 0;
    (area.colwise() - p).colwise().squaredNorm().minCoeff(&k);
    return Eigen::Vector3d(area.col(k));
  };
  int used_origin_points = 0;
  for (Eigen::Index k = 0; k < origin.cols(); ++k)
    for (int i = 0; i < f.count; ++i)
      if (f.attachments_mm.col(2 * i) == origin.col(k)) {
        ++used_origin_points;
        break;
      }
  for (int i = 0; i < f.count; ++i) {
    EXPECT_EQ(f.attachments_mm.col(2 * i), nearest(origin, f.points_mm.col(i * per))) << i;
    EXPECT_EQ(f.attachments_mm.col(2 * i + 1), nearest(insertion, f.points_mm.col(i * per + f.segments))) << i;
  }
  EXPECT_GE(used_origin_points, 2) << "the fibres spread over the area's points";
}

TEST(FibreLengths, TendonsToTheAttachmentsCount) {
  Eigen::Matrix3Xd points(3, 6), attachments(3, 4);
  points << 0, 1, 3, 0, 0, 0, 0, 0, 0, 0, 2, 4, 0, 0, 0, 0, 0, 0;  // fibre 0 along x, fibre 1 along y
  attachments << -1, 3, 0, 0, 0, 4, -2, 7, 0, 0, 0, 0;
  Eigen::VectorXd lengths;
  calcFibreLengths(points, 2, attachments, lengths);
  ASSERT_EQ(lengths.size(), 2);
  EXPECT_DOUBLE_EQ(lengths(0), 1.0 + 3.0 + 4.0);
  EXPECT_DOUBLE_EQ(lengths(1), 2.0 + 4.0 + 3.0);
  EXPECT_THROW(calcFibreLengths(points, 2, Eigen::Matrix3Xd(3, 3), lengths), std::invalid_argument);
}

TEST_F(RodFibres, EndsSpreadAndPairByPosition) {
  const RestFibres& f = *fibres_;
  // Spread: no two start points closer than 1 mm (farthest-point sampling on a ~1 mm grid).
  double closest = 1e9, pair_offset = 0, cross_offset = 0;
  for (int i = 0; i < f.count; ++i) {
    for (int k = i + 1; k < f.count; ++k)
      closest = std::min(closest, (f.points_mm.col(i * 11) - f.points_mm.col(k * 11)).norm());
    // On a straight rod, paired ends sit at corresponding (y, z) positions.
    pair_offset += (f.points_mm.col(i * 11).tail<2>() - f.points_mm.col(i * 11 + 10).tail<2>()).norm();
    cross_offset += (f.points_mm.col(i * 11).tail<2>() - f.points_mm.col(((i + 15) % 30) * 11 + 10).tail<2>()).norm();
  }
  EXPECT_GT(closest, 1.0);
  EXPECT_LT(pair_offset, 0.5 * cross_offset) << "pairing does not follow positions";
}

TEST_F(RodFibres, FillTheVolume) {
  const RestFibres& f = *fibres_;
  EXPECT_GT(f.ideal_radius_mm, 0.0);
  std::printf("rod coverage: %.3f within 2 r0 = %.2f mm, mean distance %.2f mm\n", f.covered_fraction, 2 * f.ideal_radius_mm, f.mean_distance_mm);
  EXPECT_GT(f.covered_fraction, 0.8) << "mean distance " << f.mean_distance_mm << " r0 " << f.ideal_radius_mm;
  EXPECT_LT(f.mean_distance_mm, 2.0 * f.ideal_radius_mm);
}

TEST_F(RodFibres, GenerationIsDeterministic) {
  const RestFibres again = generateFibres(*field_, test::rodOrigin(), test::rodInsertion(), test::makeSmallFibreSettings());
  EXPECT_EQ(again.points_mm, fibres_->points_mm);
}

TEST_F(RodFibres, ShapeDoesNotDependOnTheSegmentCount) {
  // Relaxed at S itself, fine fibres kept the grid path's zigzags: the gluteus maximus's rest
  // fibres were 19 % longer at S = 60 than at S = 15.
  FibreSettings fine = test::makeSmallFibreSettings();
  fine.segments = 60;
  const RestFibres f = generateFibres(*field_, test::rodOrigin(), test::rodInsertion(), fine);
  ASSERT_EQ(f.lengths_mm.size(), fibres_->lengths_mm.size());
  EXPECT_EQ(f.points_below_margin, 0);
  for (int i = 0; i < f.count; ++i) {
    EXPECT_NEAR(f.lengths_mm(i), fibres_->lengths_mm(i), 0.005 * fibres_->lengths_mm(i)) << "fibre " << i;
    EXPECT_EQ(f.points_mm.col(i * 61), fibres_->points_mm.col(i * 11)) << "fibre " << i << "'s origin end";
    EXPECT_EQ(f.points_mm.col(i * 61 + 60), fibres_->points_mm.col(i * 11 + 10)) << "fibre " << i << "'s insertion end";
  }
}

/// The end points (j = 0 and j = S) of every fibre.
std::vector<Eigen::Vector3d> collectEnds(const RestFibres& f) {
  std::vector<Eigen::Vector3d> ends;
  for (int i = 0; i < f.count; ++i)
    for (int j : {0, f.segments}) ends.push_back(f.points_mm.col(i * (f.segments + 1) + j));
  return ends;
}

TEST(FibreGenerator, FibresShareTheFewNodesNearASmallAreaRatherThanEndFarFromIt) {
  const GaussianField field = test::makeFibreRod();
  FibreSettings s = test::makeSmallFibreSettings();
  s.attachment_radius_mm = 2;  // a few grid nodes (1.5 mm apart) for 30 fibres
  const RestFibres f = generateFibres(field, test::rodOrigin(), test::rodInsertion(), s);
  EXPECT_EQ(f.attachment_radius_origin_mm, 2.0);
  EXPECT_EQ(f.attachment_radius_insertion_mm, 2.0);
  std::vector<Eigen::Vector3d> distinct;
  for (const Eigen::Vector3d& e : collectEnds(f)) {
    EXPECT_LE(std::min((e - test::rodOrigin().col(0)).norm(), (e - test::rodInsertion().col(0)).norm()),
              2.0 + f.end_climb_max_mm + 1e-9);
    if (std::none_of(distinct.begin(), distinct.end(), [&](const Eigen::Vector3d& d) { return (d - e).norm() < 1e-9; }))
      distinct.push_back(e);
  }
  EXPECT_GE(distinct.size(), 2u);
  EXPECT_LT(distinct.size(), 30u) << "fewer distinct ends than fibres: the fibres share them";
  Eigen::VectorXd values;
  field.calcValues(f.points_mm, values);
  EXPECT_GT(values.minCoeff(), 0.0);
}

TEST(FibreGenerator, EndsClimbFromTheirGridNodesTowardsTheEndDepthByAtMostHalfTheSpacing) {
  const GaussianField field = test::makeFibreRod();
  FibreSettings s = test::makeSmallFibreSettings();
  s.end_depth = 1e3;  // deeper than the rod: every end climbs as far as it may
  const RestFibres f = generateFibres(field, test::rodOrigin(), test::rodInsertion(), s);
  const InteriorGrid grid = makeInteriorGrid(field, s.projection.margin_mm, s.grid_nodes);  // the generator's
  EXPECT_DOUBLE_EQ(f.end_climb_max_mm, 0.5 * grid.spacing_mm);
  int climbed = 0;
  for (const Eigen::Vector3d& end : collectEnds(f)) {
    // The node it left: the nearest one (half a spacing is less than the distance between nodes).
    Eigen::Index node = 0;
    const double off = std::sqrt((grid.nodes_mm.colwise() - end).colwise().squaredNorm().minCoeff(&node));
    EXPECT_LE(off, f.end_climb_max_mm + 1e-9);
    EXPECT_GE(field.calcValue(end), grid.values(node) - 1e-12) << "an end went down";
    climbed += off > 0.1 * f.end_climb_max_mm && field.calcValue(end) > grid.values(node) + 1e-6;
  }
  EXPECT_GT(climbed, f.count) << "most of the 2N ends left their nodes uphill";
}

TEST(FibreGenerator, RegionAwayFromTheMuscleIsNamed) {
  const GaussianField field = test::makeFibreRod();
  FibreSettings s = test::makeSmallFibreSettings();
  s.attachment_radius_mm = 1;
  try {
    generateFibres(field, Eigen::Vector3d(0, 0, 500), test::rodInsertion(), s);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("near the origin region"), std::string::npos) << e.what();
  }
  s.count = 0;
  EXPECT_THROW(generateFibres(field, test::rodOrigin(), test::rodInsertion(), s), std::invalid_argument);
}

TEST(InteriorGrid, PiecesAreTheSetsJoinedByTheEdgesFibresWalk) {
  int count = 0;
  const InteriorGrid rod = makeInteriorGrid(test::makeFibreRod(), 0.5, 6000);
  const std::vector<int> rod_pieces = labelInteriorPieces(rod, count);
  EXPECT_EQ(count, 1);
  EXPECT_EQ(rod_pieces.size(), static_cast<size_t>(rod.nodes_mm.cols()));
  const InteriorGrid halves = makeInteriorGrid(test::makeFibreDumbbell(0.0), 0.5, 6000);
  const std::vector<int> half_pieces = labelInteriorPieces(halves, count);
  ASSERT_EQ(count, 2);
  for (Eigen::Index a = 0; a < halves.nodes_mm.cols(); ++a)  // numbered in node order: −x first
    EXPECT_EQ(half_pieces[static_cast<size_t>(a)], halves.nodes_mm(0, a) < 0.0 ? 0 : 1) << a;
}

TEST(FibreGenerator, FibresCrossANeckThinnerThanTheGridOnARefinedGrid) {
  const GaussianField field = test::makeFibreDumbbell(4.45);
  const FibreSettings s = test::makeSmallFibreSettings();
  int count = 0;
  labelInteriorPieces(makeInteriorGrid(field, s.projection.margin_mm, s.grid_nodes), count);
  ASSERT_GT(count, 1) << "the test needs a neck the first grid splits";
  const RestFibres f = generateFibres(field, test::rodOrigin(), test::rodInsertion(), s);
  EXPECT_GE(f.grid_refinements, 1);
  EXPECT_LE(f.grid_refinements, kMaxGridRefinements);
  EXPECT_LT(f.grid_spacing_mm, makeInteriorGrid(field, s.projection.margin_mm, s.grid_nodes).spacing_mm);
  const int per = f.segments + 1;
  for (int i = 0; i < f.count; ++i) {
    EXPECT_LT(f.points_mm(0, i * per), -14.0) << i;  // from the origin's half …
    EXPECT_GT(f.points_mm(0, i * per + f.segments), 14.0) << i;  // … to the insertion's
  }
  EXPECT_GT(f.min_value, 0.0) << "every point inside, through the neck too";
}

TEST(FibreGenerator, EndsLieInThePieceThatJoinsTheAreasNotInACrumbBesideAnArea) {
  GaussianField field = test::makeFibreRod();
  field.addCentre(Eigen::Vector3d(-45, 0, 0), 8.0, 0.25);  // a crumb beyond the rod's end
  const FibreSettings s = test::makeSmallFibreSettings();
  const InteriorGrid grid = makeInteriorGrid(field, s.projection.margin_mm, s.grid_nodes);
  int count = 0;
  labelInteriorPieces(grid, count);
  ASSERT_EQ(count, 2);
  // The rod's inside ends at x ≈ −34.6: from x = −40 the crumb is the nearer piece, from −42
  // it is the only one within r = 6 mm.
  for (const double origin_x : {-40.0, -42.0}) {
    const Eigen::Vector3d origin(origin_x, 0, 0);
    bool crumb_near_origin = false;
    for (Eigen::Index a = 0; a < grid.nodes_mm.cols(); ++a)
      crumb_near_origin |= grid.nodes_mm(0, a) < -40.0 && (grid.nodes_mm.col(a) - origin).norm() <= s.attachment_radius_mm;
    ASSERT_TRUE(crumb_near_origin) << "the test needs the crumb among the origin's candidates";
    const RestFibres f = generateFibres(field, origin, test::rodInsertion(), s);
    EXPECT_EQ(f.grid_refinements, 0);
    for (int i = 0; i < f.count; ++i) EXPECT_GT(f.points_mm(0, i * (f.segments + 1)), -40.0) << origin_x << ' ' << i;
    EXPECT_GT(f.min_value, 0.0);
  }
}

TEST(FibreGenerator, AMuscleInTwoPiecesIsRefusedSayingWhy) {
  try {
    generateFibres(test::makeFibreDumbbell(0.0), test::rodOrigin(), test::rodInsertion(), test::makeSmallFibreSettings());
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("reaches both the origin and the insertion"), std::string::npos) << what;
    EXPECT_NE(what.find("in 2 pieces"), std::string::npos) << what;
  }
}

/// The message of generateFibres with `settings` on the rod, and how long it took to fail (s).
std::string generationError(const FibreSettings& settings, double& seconds) {
  const GaussianField field = test::makeFibreRod();
  const auto start = std::chrono::steady_clock::now();
  std::string what = "no error";
  try {
    generateFibres(field, test::rodOrigin(), test::rodInsertion(), settings);
  } catch (const std::invalid_argument& e) {
    what = e.what();
  }
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return what;
}

TEST(FibreGenerator, SettingsBeyondTheTrackingBoundAreRefusedUpFront) {
  // 10 000 fibres × 1000 segments (the largest the RBFMuscle properties allow) ran for minutes
  // without an estimate.
  FibreSettings s = test::makeSmallFibreSettings();
  s.count = 10000;
  s.segments = 1000;
  double seconds = 0;
  const std::string what = generationError(s, seconds);
  EXPECT_NE(what.find("count 10000 × (segments 1000 + 1) = 10010000 fibre points, more than the 1000000"),
            std::string::npos)
      << what;
  EXPECT_LT(seconds, 1.0 * RBFMUSCLE_TEST_TIME_SCALE);
}

TEST(FibreGenerator, SettingsBeyondTheGenerationCostBoundAreRefusedUpFront) {
  FibreSettings s = test::makeSmallFibreSettings();
  s.count = 10000;
  s.segments = 50;
  s.smoothing_iterations = 20;
  EXPECT_DOUBLE_EQ(estimateSpreadingPairs(s), 20.0 * 1e8 * (kShapeSegments - 1));
  double seconds = 0;
  const std::string what = generationError(s, seconds);
  EXPECT_NE(what.find("need about 2.8e+10 point-pair evaluations to generate the fibres, more than the 1e+10"),
            std::string::npos)
      << what;
  EXPECT_LT(seconds, 1.0 * RBFMUSCLE_TEST_TIME_SCALE);
}

}  // namespace
}  // namespace rbfmuscle
