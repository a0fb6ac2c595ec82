// SPDX-License-Identifier: Apache-2.0
#include "framework/frame_state.h"

#include <gtest/gtest.h>

#include "framework/framework_error.h"
#include "model/skeleton.h"

namespace rbfmuscle {
namespace {

const std::string kHip = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip";

class InitContextPaths : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { skeleton_ = new Skeleton(Skeleton::fromUrdf(kHip + "/hip_r.urdf")); }
  static void TearDownTestSuite() { delete skeleton_; }
  static Skeleton* skeleton_;
};
Skeleton* InitContextPaths::skeleton_ = nullptr;

TEST_F(InitContextPaths, RelativePathsResolveInsideTheModelDirectory) {
  const InitContext context("/models/hip", "/out", *skeleton_);
  EXPECT_EQ(context.resolvePath("surfaces/gluteus.rbf"), "/models/hip/surfaces/gluteus.rbf");
  EXPECT_EQ(context.resolvePath("./meshes/../surfaces/x.rbf"), "/models/hip/surfaces/x.rbf");
}

TEST_F(InitContextPaths, RelativePathLeavingTheModelDirectoryIsRefused) {
  // A surface_file of ../../../tmp/x.rbf wrote the fit outside the model.
  const InitContext context("/models/hip", "/out", *skeleton_);
  for (const char* path : {"../../../tmp/x.rbf", "surfaces/../../x.rbf", ".."}) {
    try {
      context.resolvePath(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const FrameworkError& e) {
      EXPECT_NE(std::string(e.what()).find("path '" + std::string(path) + "' leaves the model directory /models/hip"),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("write an absolute path"), std::string::npos) << e.what();
    }
  }
}

TEST_F(InitContextPaths, AbsolutePathIsTheUsersChoiceAndKeptAsWritten) {
  const InitContext context("/models/hip", "/out", *skeleton_);
  EXPECT_EQ(context.resolvePath("/tmp/x.rbf"), "/tmp/x.rbf");
}

}  // namespace
}  // namespace rbfmuscle
