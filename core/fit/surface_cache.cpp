// SPDX-License-Identifier: Apache-2.0
#include "fit/surface_cache.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "fit/fit_pipeline.h"
#include "geometry/mesh_io.h"
#include "io/file_checks.h"
#include "geometry/mesh_warning.h"

namespace rbfmuscle {

RbfSurface loadOrFitSurface(const std::string& mesh_path, const std::string& rbf_path,
                            const FitSettings& settings, SurfaceOrigin& origin,
                            const std::function<void(const std::string&)>& log,
                            const MeshAdjustFn& adjust) {
  // The mesh must be a regular file before anything reads or hashes it (a device never ends).
  {
    const std::string problem = io::findInputFileProblem(mesh_path, "a mesh file");
    if (!problem.empty()) throw MeshError(mesh_path + ": " + problem);
  }
  std::error_code ec;
  const bool cached = !rbf_path.empty() && std::filesystem::exists(rbf_path, ec);
  if (cached) {
    RbfSurface surface = readRbfFile(rbf_path);
    const std::string hash = hashFile(mesh_path);
    if (surface.source_hash != hash) {
      // Before blaming the cache, make sure the mesh file is a mesh at all: a mesh_file naming
      // some other file should be reported as that, not as a stale cache.
      readMesh(mesh_path);
      const std::string mesh_name = std::filesystem::path(mesh_path).filename().string();
      const std::string names = surface.source_mesh == mesh_name
                                    ? ""
                                    : " (the .rbf was fitted to '" + surface.source_mesh + "', mesh_file names '" +
                                          mesh_name + "': is mesh_file right?)";
      throw RbfFileError(rbf_path + ": fitted to a mesh with hash " + surface.source_hash + ", but " +
                         mesh_path + " now has hash " + hash + names +
                         "; if the mesh changed on purpose, delete the .rbf file to refit (it is never refitted "
                         "silently)");
    }
    origin = SurfaceOrigin::kCache;
    return surface;
  }
  if (log)
    log("fitting " + mesh_path + " with " + std::to_string(settings.max_centres) + " centres" +
        (rbf_path.empty() ? " (no cache file set)" : " (no cache yet at " + rbf_path + ")"));
  const FitProgressFn progress = [&log](const FitProgress& p) {
    if (log && (p.round % 10 == 0 || p.centres == p.max_centres))
      log("  fit round " + std::to_string(p.round) + ": " + std::to_string(p.centres) + "/" +
          std::to_string(p.max_centres) + " centres, rms surface error " + std::to_string(p.rms_surface_mm) + " mm");
  };
  MeshFit fit = fitMeshFile(mesh_path, settings, false, progress, adjust);
  if (log) log("  fitted: " + fit.surface.metrics_json);
  for (const std::string& warning : fit.warnings) printMeshWarning(warning);
  if (!rbf_path.empty()) writeRbfFile(rbf_path, fit.surface);
  origin = SurfaceOrigin::kFitted;
  return std::move(fit.surface);
}

}  // namespace rbfmuscle
