// SPDX-License-Identifier: Apache-2.0
#include "geometry/solid_mesh.h"

#include <utility>

#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_repair.h"

namespace rbfmuscle {

TriangleMesh loadSolidMesh(const std::string& path, const SolidMeshOptions& options) {
  LoadedMesh loaded = readMesh(path);
  std::string warning = loaded.describeDefects(path);
  if (options.fix_winding && orientConsistently(loaded.mesh) > 0 && loaded.repair.leftDefects()) {
    // Pinches are split only on a consistently wound mesh: try again once it is.
    loaded.repair = repairMesh(loaded.mesh);
    warning += "; after rewinding: " + loaded.repair.describe();
  }
  if (!warning.empty() && options.warn) options.warn(warning);
  try {
    validateMesh(loaded.mesh, path);
  } catch (const MeshError& error) {
    if (!loaded.repair.leftDefects()) throw;
    throw MeshError(std::string(error.what()) + "; the loader could not repair it: " + loaded.repair.describe());
  }
  return std::move(loaded.mesh);
}

}  // namespace rbfmuscle
