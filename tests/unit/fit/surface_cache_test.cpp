// SPDX-License-Identifier: Apache-2.0
#include "fit/surface_cache.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "geometry/mesh_error.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

const fs::path kHip = fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip";

fs::path testDir(const std::string& name) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/surface_cache" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The message of what loadOrFitSurface throws (any exception), or "no error".
std::string loadError(const std::string& mesh, const std::string& rbf) {
  SurfaceOrigin origin = SurfaceOrigin::kCache;
  try {
    loadOrFitSurface(mesh, rbf, FitSettings{}, origin);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST(SurfaceCache, MeshFileThatIsNotAMeshIsReportedAsSuchNotAsAStaleCache) {
  // mesh_file naming some other file (here a text file) used to be hashed and the message
  // advised deleting the .rbf.
  const fs::path dir = testDir("not_a_mesh");
  const fs::path text = dir / "notes.txt";
  std::ofstream(text) << "root:x:0:0:root:/root:/bin/bash\n";
  const std::string error = loadError(text.string(), (kHip / "surfaces/gluteus_maximus_r.rbf").string());
  EXPECT_NE(error.find(text.string() + ": cannot read mesh"), std::string::npos) << error;
  EXPECT_EQ(error.find("delete the .rbf"), std::string::npos) << error;
}

TEST(SurfaceCache, AnotherMeshIsReportedWithBothFileNames) {
  const std::string error = loadError((kHip / "meshes/iliacus_r.ply").string(),
                                      (kHip / "surfaces/gluteus_maximus_r.rbf").string());
  EXPECT_NE(error.find("the .rbf was fitted to 'gluteus_maximus_r.ply', mesh_file names 'iliacus_r.ply'"),
            std::string::npos)
      << error;
}

TEST(SurfaceCache, MeshPathThatIsADeviceIsRefusedBeforeItIsReadOrHashed) {
  // /dev/urandom as mesh_file with a cache present was hashed forever.
  const std::string error = loadError("/dev/urandom", (kHip / "surfaces/gluteus_maximus_r.rbf").string());
  EXPECT_NE(error.find("/dev/urandom: is a character device, not a regular file"), std::string::npos) << error;
}

TEST(SurfaceCache, MatchingCacheIsRead) {
  SurfaceOrigin origin = SurfaceOrigin::kFitted;
  const RbfSurface s = loadOrFitSurface((kHip / "meshes/gluteus_maximus_r.ply").string(),
                                        (kHip / "surfaces/gluteus_maximus_r.rbf").string(), FitSettings{}, origin);
  EXPECT_EQ(origin, SurfaceOrigin::kCache);
  EXPECT_EQ(s.field.getNumCentres(), 1000);
}

}  // namespace
}  // namespace rbfmuscle
