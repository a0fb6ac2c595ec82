// SPDX-License-Identifier: Apache-2.0
// Fuzz target: PLY meshes (ASCII and binary) through the whole mesh loader: the PLY reader, the
// coordinate checks, welding and repair (parseMesh, as readMesh does for a .ply file).
#include "fuzz_support.h"
#include "geometry/mesh_error.h"
#include "geometry/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rbfmuscle;
  try {
    const LoadedMesh loaded = parseMesh(fuzz::asText(data, size), "fuzz.ply");
    fuzz::requireThat(loaded.mesh.vertices_mm.allFinite(), "a loaded mesh has finite vertices");
    fuzz::requireThat(loaded.mesh.countTriangles() > 0, "a loaded mesh has triangles");
  } catch (const MeshError&) {
  }
  return 0;
}
