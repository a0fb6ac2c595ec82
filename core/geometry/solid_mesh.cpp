// SPDX-License-Identifier: Apache-2.0
#include "geometry/solid_mesh.h"

#include <utility>

#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"

namespace rbfmuscle {

TriangleMesh loadSolidMesh(const std::string& path, const SolidMeshOptions& options) {
  LoadedMesh loaded = readMesh(path);
  const std::string warning = loaded.describeDefects(path);
  if (!warning.empty() && options.warn) options.warn(warning);
  if (options.fix_winding) orientConsistently(loaded.mesh);
  try {
    validateMesh(loaded.mesh, path);
  } catch (const MeshError& error) {
    if (!loaded.repair.leftDefects()) throw;
    throw MeshError(std::string(error.what()) + "; the loader could not repair it: " + loaded.repair.describe());
  }
  return std::move(loaded.mesh);
}

}  // namespace rbfmuscle
