#pragma once
/// @file
/// Fitted surfaces cached by mesh hash: a run reuses a .rbf file fitted to the
/// very same mesh bytes and never refits silently.
#include <functional>
#include <string>

#include "fit/fit_settings.h"
#include "fit/rbf_file.h"

namespace rbfmuscle {

/// Where a surface came from.
enum class SurfaceOrigin { kCache, kFitted };

/// Returns the surface of `mesh_path`:
/// - `rbf_path` exists and its source_hash equals the mesh file's hash → read it;
/// - `rbf_path` exists with another hash → RbfFileError naming both files and
///   hashes (the mesh changed: delete the cache to refit);
/// - `rbf_path` does not exist (or is empty) → fit with `settings`, say so
///   through `log` (with progress), and write the cache when a path is given.
/// @throws RbfFileError, MeshError, std::invalid_argument.
RbfSurface loadOrFitSurface(const std::string& mesh_path, const std::string& rbf_path,
                            const FitSettings& settings, SurfaceOrigin& origin,
                            const std::function<void(const std::string&)>& log = {});

}  // namespace rbfmuscle
