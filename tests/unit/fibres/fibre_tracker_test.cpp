#include "fibres/fibre_tracker.h"

#include "dynamics/muscle_deformer.h"
#include "fibre_test_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rbfmuscle {
namespace {

struct RodSetup {
  GaussianField field = test::makeFibreRod();
  Attachments attachments = test::makeFibreRodAttachments(field);
  RestFibres rest = generateFibres(field, test::rodOrigin(), test::rodInsertion(), test::makeSmallFibreSettings());
  FibreTracker tracker{rest, field.getCentres(), attachments, 0, 1, 20.0};
};

/// Bone 0 at rest, bone 1 turned about z through the rod's middle.
std::vector<Eigen::Isometry3d> bend(double angle_rad) {
  return {Eigen::Isometry3d::Identity(), test::makeTurn(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), angle_rad)};
}

TEST(FibreTracker, RestPoseGivesRestLengths) {
  RodSetup s;
  const FibreFrame& frame = s.tracker.update(s.field, bend(0.0));
  EXPECT_EQ(frame.projected, 0);
  EXPECT_EQ(frame.outside, 0);
  EXPECT_LT((frame.points_mm - s.rest.points_mm).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(frame.normalised_mean, 1.0, 1e-12);
  EXPECT_LE(frame.min_mm, frame.mean_mm);
  EXPECT_LE(frame.mean_mm, frame.max_mm);
}

TEST(FibreTracker, EndPointsWeighOnlyOnTheirBone) {
  RodSetup s;
  const Eigen::MatrixXd& w = s.tracker.getWeights();
  for (int i = 0; i < s.rest.count; ++i) {
    EXPECT_EQ(w(0, i * 11), 1.0);
    EXPECT_EQ(w(1, i * 11), 0.0);
    EXPECT_EQ(w(1, i * 11 + 10), 1.0);
    EXPECT_EQ(w(0, i * 11 + 10), 0.0);
  }
  for (Eigen::Index c = 0; c < w.cols(); ++c) EXPECT_NEAR(w.col(c).sum(), 1.0, 1e-12);
}

TEST(FibreTracker, RigidMotionOfTheSceneKeepsTheLengths) {
  RodSetup s;
  Eigen::Isometry3d x = test::makeTurn(Eigen::Vector3d(5, -3, 2), Eigen::Vector3d(1, 1, 0.3), 0.9);
  x.translation() += Eigen::Vector3d(200, -100, 50);
  GaussianField moved = s.field;
  moved.setCentrePositions(x * s.field.getCentres());
  const FibreFrame& frame = s.tracker.update(moved, {x, x});
  EXPECT_EQ(frame.projected, 0);
  for (int i = 0; i < s.rest.count; ++i)
    EXPECT_NEAR(frame.lengths_mm(i) / s.rest.lengths_mm(i), 1.0, 1e-6) << "fibre " << i;
  EXPECT_LT((frame.points_mm - x * s.rest.points_mm).cwiseAbs().maxCoeff(), 1e-9);
}

/// Ends are rigid with their bone but pushed in when the field drops under them: lowering
/// the offset until some ends sit below the margin moves them by at most end_max_move_mm,
/// each along its ascent, and brings one that fell just outside (f = −0.1) back inside.
TEST(FibreTracker, EndsBelowTheMarginMoveInByAtMostTheEndCap) {
  RodSetup s;
  const int per = s.rest.segments + 1;
  Eigen::VectorXd rest_values;
  s.field.calcValues(s.rest.points_mm, rest_values);
  double lowest_end = INFINITY;
  for (int i = 0; i < s.rest.count; ++i)
    lowest_end = std::min({lowest_end, rest_values(i * per), rest_values(i * per + s.rest.segments)});
  GaussianField lowered = s.field;
  lowered.setOffset(s.field.getOffset() - (lowest_end + 0.1));  // the shallowest end now outside, f = −0.1
  const FibreFrame& frame = s.tracker.update(lowered, bend(0.0));
  EXPECT_GT(frame.projected, 0);
  EXPECT_GT(frame.end_offset_max_mm, 0.0);
  EXPECT_LE(frame.end_offset_max_mm, ProjectionSettings{}.end_max_move_mm + 1e-12);
  Eigen::VectorXd values;
  lowered.calcValues(frame.points_mm, values);
  for (int i = 0; i < s.rest.count; ++i)
    for (int j : {0, s.rest.segments}) {
      const Eigen::Index c = static_cast<Eigen::Index>(i) * per + j;
      EXPECT_LE((frame.points_mm.col(c) - s.rest.points_mm.col(c)).norm(), frame.end_offset_max_mm + 1e-12);
      EXPECT_GE(values(c), rest_values(c) - (lowest_end + 0.1) - 1e-12) << "f never drops, fibre " << i;
    }
  EXPECT_EQ(frame.outside, 0);
}

/// The rod bent by the MuscleDeformer in 1° frames to 60° about the middle.
class BentRod : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    setup_ = new RodSetup();
    DeformerSettings settings;
    settings.quadrature.target_count = 1500;
    settings.descent.max_iterations = 20;
    MuscleDeformer deformer(setup_->field, setup_->attachments, settings);
    for (int degree = 0; degree <= 60; ++degree) {
      const std::vector<Eigen::Isometry3d> motion = bend(degree * M_PI / 180.0);
      deformer.update(motion);
      frames_.push_back(setup_->tracker.update(deformer.getField(), motion));
      fields_.push_back(deformer.getField());
    }
  }
  static void TearDownTestSuite() { delete setup_; }
  static RodSetup* setup_;
  static std::vector<FibreFrame> frames_;
  static std::vector<GaussianField> fields_;
};
RodSetup* BentRod::setup_ = nullptr;
std::vector<FibreFrame> BentRod::frames_;
std::vector<GaussianField> BentRod::fields_;

TEST_F(BentRod, EveryPointStaysInside) {
  int projected = 0;
  for (size_t a = 0; a < frames_.size(); ++a) {
    Eigen::VectorXd values;
    fields_[a].calcValues(frames_[a].points_mm, values);
    EXPECT_GT(values.minCoeff(), 0.0) << a << "°";
    EXPECT_EQ(frames_[a].outside, 0) << a << "°";
    projected += frames_[a].projected;
  }
  std::printf("bent rod: %d projections over 61 frames of %d points\n", projected,
              static_cast<int>(frames_[0].points_mm.cols()));
}

TEST_F(BentRod, EndPointsFollowTheirBones) {
  const RestFibres& rest = setup_->rest;
  for (size_t a = 0; a < frames_.size(); a += 10) {
    const std::vector<Eigen::Isometry3d> motion = bend(static_cast<double>(a) * M_PI / 180.0);
    for (int i = 0; i < rest.count; ++i) {
      EXPECT_LT((frames_[a].points_mm.col(i * 11) - motion[0] * Eigen::Vector3d(rest.points_mm.col(i * 11))).norm(), 0.5);
      EXPECT_LT((frames_[a].points_mm.col(i * 11 + 10) - motion[1] * Eigen::Vector3d(rest.points_mm.col(i * 11 + 10))).norm(),
                0.5);
    }
  }
}

TEST_F(BentRod, LengthsAreContinuousAndTheInnerSideShortens) {
  for (size_t a = 1; a < frames_.size(); ++a)
    for (Eigen::Index i = 0; i < frames_[a].lengths_mm.size(); ++i)
      EXPECT_LT(std::abs(frames_[a].lengths_mm(i) / frames_[a - 1].lengths_mm(i) - 1.0), 0.01) << a << "° fibre " << i;
  // Turning +z about the middle bends the rod towards +y: fibres on the −y (outer) side
  // stretch more than those on the +y (inner) side. (Both sides may lengthen: the blend
  // turns the free middle about the pivot by graded angles, as it does the centres.)
  const RestFibres& rest = setup_->rest;
  const FibreFrame& last = frames_.back();
  double inner = 0, outer = 0;
  int n_inner = 0, n_outer = 0;
  for (int i = 0; i < rest.count; ++i) {
    const double y = rest.points_mm.row(1).segment(i * 11, 11).mean();
    const double ratio = last.lengths_mm(i) / rest.lengths_mm(i);
    if (y > 2) {
      inner += ratio;
      ++n_inner;
    } else if (y < -2) {
      outer += ratio;
      ++n_outer;
    }
  }
  ASSERT_GT(n_inner, 3);
  ASSERT_GT(n_outer, 3);
  std::printf("bent rod 60°: inner side mean ratio %.4f, outer side %.4f\n", inner / n_inner, outer / n_outer);
  EXPECT_GT(outer / n_outer, inner / n_inner + 0.02);
}

TEST(FibreTracker, BadInputIsRefused) {
  RodSetup s;
  EXPECT_THROW(FibreTracker(s.rest, s.field.getCentres(), s.attachments, 0, 2, 20.0), std::invalid_argument);
  EXPECT_THROW(s.tracker.update(s.field, {Eigen::Isometry3d::Identity()}), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
