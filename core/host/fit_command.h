// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// `rbfmuscle fit`: mesh in, fitted .rbf surface (and optionally its
/// extracted mesh) out, figures as the last stdout line (one JSON object).
/// Parsing, checks, fit and writing are separate calls, so the Python module's fit() takes
/// the same path with the same messages.
#include "fit/fit_pipeline.h"
#include "geometry/triangle_mesh.h"

#include <functional>
#include <string>
#include <vector>

namespace rbfmuscle {

/// A `fit` command line, parsed.
struct FitJob {
  std::string mesh_path;
  std::string output_path;   ///< -o: the .rbf written ("" = none, only without require_output)
  std::string surface_path;  ///< --surface: the extracted surface as PLY ("" = none)
  FitSettings settings;
  bool fix_winding = false;
  bool quiet = false;
  bool help = false;                  ///< -h: nothing else was parsed
  std::vector<double> global_search;  ///< --global-search LO,HI,K ({} = none)
  std::vector<std::string> out_of;    ///< --out-of: solids the mesh is moved out of first ({} = none)
};

/// Parses the arguments after "fit" and checks the settings, before any file is read.
/// @param require_output -o is required (the command; the Python module may fit in memory)
/// @throws UsageError with the command's message
FitJob parseFitArguments(const std::vector<std::string>& args, bool require_output);

/// Checks the files (no output is an input or the other output; the mesh is a regular file;
/// every output can be written), loads the --out-of solids, then fits the mesh moved out of
/// them (fitMeshFile, or fitMeshFileGlobalShape with --global-search; `global_report` hears
/// each shape tried and its C_m). Writes nothing.
/// @throws UsageError or std::runtime_error naming the file, and what fitMeshFile throws
MeshFit runFitJob(const FitJob& job, const FitProgressFn& progress,
                  const std::function<void(double alpha, double metric)>& global_report = {});

/// Writes the .rbf and the surface PLY the job names, all or none.
void writeFitOutputs(const FitJob& job, const MeshFit& fit);

/// The fitted surface's extracted mesh in the source mesh's frame (mm), as --surface writes it.
TriangleMesh fittedSurfaceInSourceFrame(const MeshFit& fit);

/// Runs `rbfmuscle fit`; argv[0] is "fit". Returns the exit code; throws
/// UsageError for a bad command line and other exceptions for bad input.
int runFitCommand(int argc, char** argv);

}  // namespace rbfmuscle
