// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_warning.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

TEST(MeshWarning, EachWarningIsWrittenToStderrOnceWithThePrefix) {
  testing::internal::CaptureStderr();
  printMeshWarning("first.ply: 2 unused vertices dropped");
  printMeshWarning("second.ply: 1 unused vertex dropped");
  printMeshWarning("first.ply: 2 unused vertices dropped");
  const std::string written = testing::internal::GetCapturedStderr();
  EXPECT_EQ(written,
            "rbfmuscle: warning: first.ply: 2 unused vertices dropped\n"
            "rbfmuscle: warning: second.ply: 1 unused vertex dropped\n");
}

}  // namespace
}  // namespace rbfmuscle
