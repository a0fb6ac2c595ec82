// SPDX-License-Identifier: Apache-2.0
// Fuzz target: VTK XML PolyData (.vtp): every encoding the reader takes (ASCII, base64, appended
// raw, zlib), the triangulation of polygons and strips, and the mesh checks after them.
#include "fuzz_support.h"
#include "geometry/mesh_error.h"
#include "geometry/mesh_io.h"
#include "geometry/vtp_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rbfmuscle;
  const std::string text = fuzz::asText(data, size);
  try {
    const VtpPolyData vtp = parseVtpPolyData(text, "fuzz.vtp");
    fuzz::requireThat(vtp.points.allFinite(), "a read .vtp has finite points");
    const Eigen::Matrix3Xi triangles = vtp.triangulate();
    for (Eigen::Index j = 0; j < triangles.cols(); ++j)
      for (int k = 0; k < 3; ++k)
        fuzz::requireThat(triangles(k, j) >= 0 && triangles(k, j) < vtp.points.cols(),
                          "triangle corners index the points");
    parseMesh(text, "fuzz.vtp");
  } catch (const MeshError&) {
  }
  return 0;
}
