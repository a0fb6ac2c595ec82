// SPDX-License-Identifier: Apache-2.0
/// projectInside, placeBetweenInsideNeighbours and climbByPatternSearch on small analytic fields: a thin rod
/// thinner than one projection step (max f < margin), a thick rod, the flat field far
/// outside, and an arc whose chord leaves the muscle.
#include "fibres/fibre_projection.h"
#include "rbf/gaussian_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rbfmuscle {
namespace {

/// A straight rod along x: Gaussians every 1 mm on x ∈ [−30, 30], α = 0.5 mm⁻², offset −1.
/// Near x = 0 the sum is radial: f(r) ≈ A·exp(−0.5 r²) − 1 with A = λ·√(π/α) = λ·√(2π)
/// (r = distance to the x axis, mm), so max f = A − 1 on the axis.
GaussianField makeRod(double peak_value) {
  const int n = 61;
  Eigen::Matrix3Xd xi(3, n);
  const double lambda = (peak_value + 1.0) / std::sqrt(2.0 * M_PI);
  for (int i = 0; i < n; ++i) xi.col(i) = Eigen::Vector3d(-30.0 + i, 0, 0);
  return GaussianField(-1.0, xi, Eigen::VectorXd::Constant(n, lambda), Eigen::VectorXd::Constant(n, 0.5));
}

TEST(ProjectInside, TheRodFieldIsTheRadialProfile) {
  const GaussianField rod = makeRod(0.1);
  for (double r : {0.0, 0.3, 1.0})
    EXPECT_NEAR(rod.calcValue(Eigen::Vector3d(0.2, r, 0)), 1.1 * std::exp(-0.5 * r * r) - 1.0, 1e-9) << r;
}

/// The failure seen on the gluteus: a part thinner than one step, whose max f (0.1) is below
/// the margin (0.5). Newton on f = 2·margin from just inside the axis gives a step longer than
/// max_step_mm, cut to 1 mm, which crosses the whole rod (inside width 2·0.44 mm) and lands
/// outside: the old projection oscillated across the rod and could stop outside.
TEST(ProjectInside, AThinPartBelowTheMarginEndsInsideAtItsRidge) {
  const GaussianField rod = makeRod(0.1);
  const ProjectionSettings settings;  // margin 0.5, 1 mm steps, 30 steps
  // The failure mode: one capped Newton step from near the ridge lands outside.
  const Eigen::Vector3d near_ridge(0, 0.05, 0.02);
  const Eigen::Vector3d g = rod.calcGradient(near_ridge);
  Eigen::Vector3d newton = (2 * settings.margin_mm - rod.calcValue(near_ridge)) / g.squaredNorm() * g;
  ASSERT_GT(newton.norm(), settings.max_step_mm);
  newton *= settings.max_step_mm / newton.norm();
  ASSERT_GT(rod.calcValue(near_ridge), 0.0);
  ASSERT_LT(rod.calcValue(near_ridge + newton), 0.0);
  // The ascent ends inside, near the ridge, from either side and from near the ridge itself.
  for (const Eigen::Vector3d& start : {Eigen::Vector3d(0, 1.0, 0.3), Eigen::Vector3d(0, -0.7, 0.5), near_ridge}) {
    Eigen::Vector3d p = start;
    const ProjectionResult r = projectInside(rod, settings, p);
    EXPECT_GT(r.value, 0.0) << start.transpose();
    EXPECT_NEAR(r.value, rod.calcValue(p), 1e-12);
    EXPECT_GE(r.value, rod.calcValue(start));
    EXPECT_GT(r.value, 0.09) << "not at the ridge (max f = 0.1)";
    EXPECT_NE(r.stop, ProjectionStop::kReached);  // the margin cannot be reached
    EXPECT_LE(r.steps, settings.max_steps);
  }
}

TEST(ProjectInside, AThickPartReachesTheMarginAndAnInsidePointStays) {
  const GaussianField rod = makeRod(3.0);  // max f = 3, inside radius √(2 ln 4) = 1.67 mm
  const ProjectionSettings settings;
  Eigen::Vector3d p(0, 2.5, 0);
  ASSERT_LT(rod.calcValue(p), 0.0);
  const ProjectionResult r = projectInside(rod, settings, p);
  EXPECT_EQ(r.stop, ProjectionStop::kReached);
  EXPECT_GE(r.value, settings.margin_mm);
  EXPECT_NEAR(p.x(), 0.0, 1e-9);  // moved along ∇f, straight towards the axis
  Eigen::Vector3d q(0, 0.2, 0);
  const Eigen::Vector3d q0 = q;
  const ProjectionResult inside = projectInside(rod, settings, q);
  EXPECT_EQ(inside.stop, ProjectionStop::kWasInside);
  EXPECT_EQ(inside.steps, 0);
  EXPECT_EQ(q, q0);
}

/// Fibre lengths must change continuously with the pose: a point that falls a little below
/// the margin moves a little, in proportion, not to a fixed depth inside.
TEST(ProjectInside, APointJustBelowTheMarginMovesInProportionToItsShortfall) {
  const GaussianField rod = makeRod(3.0);
  const ProjectionSettings settings;
  // On the rod f(r) = 4·exp(−r²/2) − 1; f = margin at r = √(2 ln(4 / 1.5)).
  const double r_margin = std::sqrt(2.0 * std::log(4.0 / (1.0 + settings.margin_mm)));
  for (double shortfall_mm : {1e-3, 1e-2, 1e-1}) {
    Eigen::Vector3d p(0.0, r_margin + shortfall_mm, 0.0);
    ASSERT_LT(rod.calcValue(p), settings.margin_mm);
    const ProjectionResult r = projectInside(rod, settings, p);
    EXPECT_GE(r.value, settings.margin_mm);
    EXPECT_LT(r.moved_mm, 1.1 * shortfall_mm + 0.03) << shortfall_mm;  // the aim lies 0.01 above the margin
  }
}

TEST(ProjectInside, FarOutsideWithoutSlopeStopsAndSaysSo) {
  const GaussianField rod = makeRod(3.0);
  Eigen::Vector3d p(0, 40, 0);  // every Gaussian below the cutoff: f = −1, ∇f = 0
  const Eigen::Vector3d p0 = p;
  const ProjectionResult r = projectInside(rod, ProjectionSettings{}, p);
  EXPECT_EQ(r.stop, ProjectionStop::kNoAscent);
  EXPECT_EQ(r.steps, 0);
  EXPECT_EQ(p, p0);
}

TEST(ProjectInside, TooFewStepsStopAtTheCapWithFHigherThanAtTheStart) {
  const GaussianField rod = makeRod(3.0);
  ProjectionSettings settings;
  settings.max_step_mm = 0.1;
  settings.max_steps = 3;
  Eigen::Vector3d p(0, 2.5, 0);
  const double f0 = rod.calcValue(p);
  const ProjectionResult r = projectInside(rod, settings, p);
  EXPECT_EQ(r.stop, ProjectionStop::kStepCap);
  EXPECT_EQ(r.steps, 3);
  EXPECT_GT(r.value, f0);
  EXPECT_NEAR(p.y(), 2.2, 1e-9);
}

TEST(ProjectInside, TheMoveCapBoundsThePathAndSaysSo) {
  const GaussianField rod = makeRod(3.0);  // inside radius 1.67 mm
  Eigen::Vector3d p(0, 2.5, 0);
  const double f0 = rod.calcValue(p);
  const ProjectionResult r = projectInside(rod, ProjectionSettings{}, p, 0.3);
  EXPECT_EQ(r.stop, ProjectionStop::kMoveCap);
  EXPECT_NEAR(r.moved_mm, 0.3, 1e-12);
  EXPECT_NEAR(p.y(), 2.2, 1e-9);  // straight down ∇f, exactly the cap
  EXPECT_GT(r.value, f0);
  // With room enough the same start reaches the margin within the cap.
  Eigen::Vector3d q(0, 1.8, 0);
  const ProjectionResult reached = projectInside(rod, ProjectionSettings{}, q, 1.0);
  EXPECT_EQ(reached.stop, ProjectionStop::kReached);
  EXPECT_LE(reached.moved_mm, 1.0);
  EXPECT_NEAR(reached.moved_mm, 1.8 - q.y(), 1e-9);
  Eigen::Vector3d bad(0, 2.5, 0);
  EXPECT_THROW(projectInside(rod, ProjectionSettings{}, bad, -0.1), std::invalid_argument);
}

/// A thick arc (radius 40 mm, α = 0.5 mm⁻², Gaussians every 0.5°) from −60° to 60° in the
/// z = 0 plane, f ≈ 3 on it: the chord between its points at ±45° runs ≥ 7 mm from the arc,
/// through empty space (f = offset, ∇f = 0) where the ascent cannot start.
GaussianField makeArc() {
  const int n = 241;
  Eigen::Matrix3Xd xi(3, n);
  for (int i = 0; i < n; ++i) {
    const double a = (-60.0 + 0.5 * i) * M_PI / 180.0;
    xi.col(i) = 40.0 * Eigen::Vector3d(std::cos(a), std::sin(a), 0);
  }
  const double spacing_mm = 40.0 * 0.5 * M_PI / 180.0;
  const double lambda = 4.0 / std::sqrt(2.0 * M_PI) * spacing_mm;  // line density A = 4: f ≈ 3 on the arc
  return GaussianField(-1.0, xi, Eigen::VectorXd::Constant(n, lambda), Eigen::VectorXd::Constant(n, 0.5));
}

TEST(PlaceBetweenInsideNeighbours, APointOnAChordThroughEmptySpaceIsPlacedInside) {
  const GaussianField arc = makeArc();
  const double a45 = 45 * M_PI / 180;
  const Eigen::Vector3d a = 40.0 * Eigen::Vector3d(std::cos(a45), -std::sin(a45), 0);
  const Eigen::Vector3d b = 40.0 * Eigen::Vector3d(std::cos(a45), std::sin(a45), 0);
  ASSERT_GT(arc.calcValue(a), 1.0);
  ASSERT_GT(arc.calcValue(b), 1.0);
  for (double t : {0.3, 0.5, 0.8}) {
    Eigen::Vector3d p = a + t * (b - a);
    Eigen::Vector3d stuck = p;
    ASSERT_EQ(projectInside(arc, ProjectionSettings{}, stuck).stop, ProjectionStop::kNoAscent) << t;
    ASSERT_LE(arc.calcValue(stuck), 0.0);
    const double f = placeBetweenInsideNeighbours(arc, ProjectionSettings{}, a, b, t, p);
    EXPECT_GT(f, 0.0) << t;
    EXPECT_NEAR(f, arc.calcValue(p), 1e-12);
    // Between the chord point and the nearer neighbour, not past it.
    const Eigen::Vector3d& nearer = t <= 0.5 ? a : b;
    EXPECT_LE((p - nearer).norm(), (a + t * (b - a) - nearer).norm() + 1e-9) << t;
  }
}

TEST(PlaceBetweenInsideNeighbours, AnInsideChordPointOnlyMovesUp) {
  const GaussianField rod = makeRod(3.0);
  const Eigen::Vector3d a(-5, 0, 0), b(5, 0.4, 0);
  Eigen::Vector3d p(100, 100, 100);
  const double f = placeBetweenInsideNeighbours(rod, ProjectionSettings{}, a, b, 0.5, p);
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(0, 0.2, 0), 1e-12));  // f(chord point) ≥ margin: kept
  EXPECT_NEAR(f, rod.calcValue(p), 1e-12);
}

/// Two balls of radius 10 mm, centred at x = 0 and x = 25 (f = 10 − distance to the nearer centre).
struct TwoBalls final : ImplicitField {
  double calcValue(const Eigen::Vector3d& p) const override {
    return 10.0 - std::min(p.norm(), (p - Eigen::Vector3d(25, 0, 0)).norm());
  }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d&) const override { return Eigen::Vector3d::Zero(); }
};

TEST(AdvanceInside, StopsWhereTheSegmentFirstLeavesTheMuscle) {
  const TwoBalls balls;
  const ProjectionSettings settings;  // margin 0.5, samples 1 mm apart, 10 halvings
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  // Towards the other ball: the first exit (x = 9.5), not the inside beyond the gap.
  const Eigen::Vector3d first_exit = advanceInside(balls, settings, centre, Eigen::Vector3d(25, 0, 0));
  EXPECT_NEAR(first_exit.x(), 9.5, 1.0 / 1024);
  EXPECT_LE(first_exit.x(), 9.5);
  EXPECT_GE(balls.calcValue(first_exit), settings.margin_mm);
  // A segment inside is taken whole; one that starts outside is not taken.
  EXPECT_EQ(advanceInside(balls, settings, centre, Eigen::Vector3d(0, 6, 0)), Eigen::Vector3d(0, 6, 0));
  EXPECT_EQ(advanceInside(balls, settings, Eigen::Vector3d(12, 0, 0), centre), Eigen::Vector3d(12, 0, 0));
  // The exit moves continuously with the segment's end.
  const Eigen::Vector3d a = advanceInside(balls, settings, centre, Eigen::Vector3d(20, 3, 0));
  const Eigen::Vector3d b = advanceInside(balls, settings, centre, Eigen::Vector3d(20, 3.01, 0));
  EXPECT_LT((a - b).norm(), 0.01);
}

TEST(AdvanceInside, AStartJustBelowTheMarginMovesAsOneJustAboveIt) {
  const TwoBalls balls;
  const ProjectionSettings settings;  // margin 0.5
  // Starts at f = 0.5 ± 1e-9 (x = 9.5 ∓ 1e-9), heading through the ball: both cross it to
  // where f falls back to about the margin on the far side (x = −9.5).
  const Eigen::Vector3d to(-20, 0, 0);
  const Eigen::Vector3d above = advanceInside(balls, settings, Eigen::Vector3d(9.5 - 1e-9, 0, 0), to);
  const Eigen::Vector3d below = advanceInside(balls, settings, Eigen::Vector3d(9.5 + 1e-9, 0, 0), to);
  EXPECT_NEAR(above.x(), -9.5, 1.0 / 64);
  EXPECT_LT((above - below).norm(), 0.01);
  // Outside the muscle (f ≤ 0) it stays.
  EXPECT_EQ(advanceInside(balls, settings, Eigen::Vector3d(10.5, 0, 0), to), Eigen::Vector3d(10.5, 0, 0));
}

/// Counts the evaluations of the field it wraps.
struct CountedField final : ImplicitField {
  explicit CountedField(const ImplicitField& field) : field(field) {}
  double calcValue(const Eigen::Vector3d& p) const override { return ++evaluations, field.calcValue(p); }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& p) const override { return field.calcGradient(p); }
  const ImplicitField& field;
  mutable int evaluations = 0;
};

TEST(AdvanceInside, ASegmentInsideByTheMarginCostsOneEvaluationPerSample) {
  const TwoBalls balls;
  const ProjectionSettings settings;  // margin 0.5, samples 1 mm apart
  const CountedField counted(balls);
  // 6.5 mm through the ball's middle: 7 samples, none below the margin, so the start is not needed.
  EXPECT_EQ(advanceInside(counted, settings, Eigen::Vector3d(-3, 0, 0), Eigen::Vector3d(3.5, 0, 0)),
            Eigen::Vector3d(3.5, 0, 0));
  EXPECT_EQ(counted.evaluations, 7);
  // Leaving the ball: the start's level is needed once a sample falls below the margin.
  counted.evaluations = 0;
  const Eigen::Vector3d exit = advanceInside(counted, settings, Eigen::Vector3d::Zero(), Eigen::Vector3d(12, 0, 0));
  EXPECT_NEAR(exit.x(), 9.5, 1.0 / 1024);
  EXPECT_EQ(counted.evaluations, 10 + 1 + settings.max_halvings);
}

TEST(ClimbByPatternSearch, APointJustOutsideClimbsIntoTheNearerPartByAboutAStep) {
  const TwoBalls balls;  // no gradient: projectInside cannot move a point outside
  const ProjectionSettings settings;  // steps of 1 mm
  // Just outside the first ball, facing the second one 5 mm beyond the gap.
  Eigen::Vector3d p(10.1, 0, 0);
  Eigen::Vector3d stuck = p;
  ASSERT_EQ(projectInside(balls, settings, stuck).stop, ProjectionStop::kNoAscent);
  double f = climbByPatternSearch(balls, settings, p);
  EXPECT_GT(f, 0.0);
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(9.1, 0, 0), 1e-12)) << p.transpose();
  // Midway in the gap (the saddle, f = −2.5): into one ball, by the fewest steps that reach f > 0.
  p = Eigen::Vector3d(12.5, 0, 0);
  f = climbByPatternSearch(balls, settings, p);
  EXPECT_GT(f, 0.0);
  EXPECT_NEAR(std::min(p.norm(), (p - Eigen::Vector3d(25, 0, 0)).norm()), 9.5, 1e-12);
}

TEST(ClimbByPatternSearch, WithoutSlopeThePointStaysAndItsValueSaysSo) {
  const GaussianField rod = makeRod(3.0);
  Eigen::Vector3d p(0, 50, 0);  // f = offset −1 all around
  EXPECT_DOUBLE_EQ(climbByPatternSearch(rod, ProjectionSettings{}, p), -1.0);
  EXPECT_EQ(p, Eigen::Vector3d(0, 50, 0));
  // Too far for the step cap: 30 steps of 1 mm cannot climb 40 mm to the first ball.
  const TwoBalls balls;
  p = Eigen::Vector3d(-50, 0, 0);
  EXPECT_DOUBLE_EQ(climbByPatternSearch(balls, ProjectionSettings{}, p), -40.0);
  EXPECT_EQ(p, Eigen::Vector3d(-50, 0, 0));
}

TEST(FibreProjection, BadInputIsRefused) {
  const GaussianField rod = makeRod(3.0);
  Eigen::Vector3d p(0, 0, 0);
  ProjectionSettings bad;
  bad.max_halvings = -1;
  EXPECT_THROW(projectInside(rod, bad, p), std::invalid_argument);
  const Eigen::Vector3d in(0, 0, 0), out(0, 5, 0);
  EXPECT_THROW(placeBetweenInsideNeighbours(rod, ProjectionSettings{}, in, out, 0.5, p), std::invalid_argument);
  EXPECT_THROW(placeBetweenInsideNeighbours(rod, ProjectionSettings{}, in, in, 1.0, p), std::invalid_argument);
  EXPECT_THROW(placeBetweenInsideNeighbours(rod, ProjectionSettings{}, in, in, 0.5, p, 0), std::invalid_argument);
  EXPECT_THROW(climbByPatternSearch(rod, bad, p), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
