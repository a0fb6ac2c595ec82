// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Fitted surfaces cached by mesh hash: a run reuses a .rbf file fitted to the
/// very same mesh bytes and never refits silently.
#include <functional>
#include <string>

#include "fit/fit_pipeline.h"
#include "fit/fit_settings.h"
#include "fit/rbf_file.h"

namespace rbfmuscle {

/// Where a surface came from.
enum class SurfaceOrigin { kCache, kFitted };

/// Returns the surface of `mesh_path`:
/// - `rbf_path` exists and its source_hash equals the mesh file's hash → read it;
/// - `mesh_path` is not a regular file → MeshError (before anything reads or hashes it);
/// - `rbf_path` exists with another hash → first the mesh is read (readMesh), so a file that
///   is not a mesh is reported as a MeshError; then RbfFileError naming both files and
///   hashes (and both file names when they differ: the mesh changed, or mesh_file names
///   another file; delete the cache to refit);
/// - `rbf_path` does not exist (or is empty) → fit with `settings` the mesh as changed by
///   `adjust` (fitMeshFile), say so through `log` (with progress), and write the cache when a
///   path is given. The cache names the mesh file, not the change: like the fit settings, a
///   change of `adjust` needs the cache deleted.
/// @throws RbfFileError, MeshError, std::invalid_argument.
RbfSurface loadOrFitSurface(const std::string& mesh_path, const std::string& rbf_path,
                            const FitSettings& settings, SurfaceOrigin& origin,
                            const std::function<void(const std::string&)>& log = {},
                            const MeshAdjustFn& adjust = {});

}  // namespace rbfmuscle
