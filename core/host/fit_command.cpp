// SPDX-License-Identifier: Apache-2.0
#include "host/fit_command.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "fit/fit_pipeline.h"
#include "framework/interrupt.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_warning.h"
#include "geometry/move_out_of_solids.h"
#include "geometry/solid_mesh.h"
#include "host/usage_error.h"
#include "io/file_checks.h"

namespace rbfmuscle {
namespace {

const char* const kFitUsage =
    "usage: rbfmuscle fit MESH --centres N -o OUT.rbf [--surface OUT.ply] [options]\n"
    "\n"
    "Fits a Gaussian RBF implicit surface to a closed triangle mesh (mm). Progress goes to\n"
    "stderr; the last stdout line is one JSON object with jaccard, mean/p95/max_distance_mm,\n"
    "volume_ratio, centres, seconds and more.\n"
    "\n"
    "options (defaults in brackets):\n"
    "  --centres N             centre budget [1000]\n"
    "  -o, --output FILE       fitted surface (.rbf, text, versioned) — required\n"
    "  --surface FILE          also write the extracted f = 0 surface as PLY (source frame, mm)\n"
    "  --tolerance-mm T        stop early when the RMS error on surface samples ≤ T [0: off]\n"
    "  --clamp-mm TAU          clamp of the signed-distance target, at most 10000 [10]\n"
    "  --normal-offset-mm D    samples ±D along vertex normals, D ≤ TAU [1]\n"
    "  --halton N              Halton samples in the padded box [30000]\n"
    "  --check-band N          check points within the clamp of the surface [30000]\n"
    "  --no-check-layers       no check points 2D, 4D, 8D … (< TAU) off the vertices along their normals\n"
    "  --check-start F         checks begin at this fraction of the centre budget [0.75]\n"
    "  --check-slope S         a check point d from the surface wants f on its side by S·d, 0 to 1 [0.5]\n"
    "  --crumb-margin-mm E     carve bumps of f apart from the surface that come within E of it [0.5]\n"
    "  --shapes A,B,...        shape set α in mm^-2 [0.005 … 0.5]\n"
    "  --gamma G               regularisation γ of eq. 7.12, 1 = none [0.9]\n"
    "  --batch-fraction F      centres added per round / current count [0.1]\n"
    "  --cell-mm H             grid cell of the extracted surface [1]\n"
    "  --metric-points N       points for the Jaccard index (≥ 100000) [200000]\n"
    "  --global-shape ALPHA    one shape α for every centre\n"
    "  --global-search LO,HI,K search the best global α in [LO, HI] with K fits (golden section,\n"
    "                          K from 2 to 100)\n"
    "  --fix-winding           rewind inconsistently wound triangles instead of failing\n"
    "  --out-of A.ply,B.ply    closed meshes (mm, the mesh's frame) it must not lie in: vertices more\n"
    "                          than 0.5 mm inside are moved out first, as a scene does with its bones\n"
    "  --quiet                 no progress on stderr\n";

double parseNumber(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value))
    throw UsageError("fit: " + option + " expects a number, got '" + text + "'");
  return value;
}

int parseCount(const std::string& option, const std::string& text, int minimum) {
  const double value = parseNumber(option, text);
  if (value != std::floor(value) || value < minimum || value > 1e8)
    throw UsageError("fit: " + option + " expects a whole number ≥ " + std::to_string(minimum) +
                     ", got '" + text + "'");
  return static_cast<int>(value);
}

std::vector<double> parseList(const std::string& option, const std::string& text) {
  std::vector<double> values;
  std::stringstream fields(text);
  std::string item;
  while (std::getline(fields, item, ',')) values.push_back(parseNumber(option, item));
  if (values.empty()) throw UsageError("fit: " + option + " expects a comma-separated list of numbers");
  return values;
}

std::vector<std::string> parseFileList(const std::string& option, const std::string& text) {
  std::vector<std::string> files;
  std::stringstream fields(text);
  std::string item;
  while (std::getline(fields, item, ','))
    if (!item.empty()) files.push_back(item);
  if (files.empty()) throw UsageError("fit: " + option + " expects a comma-separated list of mesh files");
  return files;
}

/// Fails before a long fit when the output cannot be written.
void checkWritable(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode))
    throw std::runtime_error(path + ": output exists and is " + io::describeFileType(info.st_mode) +
                             "; refusing to replace it (give a regular file name)");
  const std::string probe = path + ".partial";
  std::ofstream out(probe);
  if (!out) throw std::runtime_error(path + ": cannot write here (does the directory exist?)");
  out.close();
  std::remove(probe.c_str());
}

}  // namespace

FitJob parseFitArguments(const std::vector<std::string>& args, bool require_output) {
  FitJob job;
  FitSettings& settings = job.settings;
  std::set<std::string> given;  // every option with a value takes one: a second would silently replace it
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw UsageError("fit: " + arg + " needs a value");
      const std::string option = arg == "--output" ? "-o" : arg;
      if (!given.insert(option).second) throw UsageError("fit: option " + option + " is given twice");
      return args[++i];
    };
    if (arg == "-h" || arg == "--help") {
      job.help = true;
      return job;
    } else if (arg == "--centres") settings.max_centres = parseCount(arg, value(), 1);
    else if (arg == "-o" || arg == "--output") job.output_path = value();
    else if (arg == "--surface") job.surface_path = value();
    else if (arg == "--tolerance-mm") settings.tolerance_mm = parseNumber(arg, value());
    else if (arg == "--clamp-mm") settings.clamp_mm = parseNumber(arg, value());
    else if (arg == "--normal-offset-mm") settings.normal_offset_mm = parseNumber(arg, value());
    else if (arg == "--halton") settings.halton_samples = parseCount(arg, value(), 0);
    else if (arg == "--check-band") settings.check_band_samples = parseCount(arg, value(), 0);
    else if (arg == "--check-start") settings.check_start_fraction = parseNumber(arg, value());
    else if (arg == "--check-slope") settings.check_slope = parseNumber(arg, value());
    else if (arg == "--crumb-margin-mm") settings.crumb_margin_mm = parseNumber(arg, value());
    else if (arg == "--no-check-layers") settings.check_normal_layers = false;
    else if (arg == "--shapes") settings.shapes_per_mm2 = parseList(arg, value());
    else if (arg == "--gamma") settings.regularisation_gamma = parseNumber(arg, value());
    else if (arg == "--batch-fraction") settings.batch_fraction = parseNumber(arg, value());
    else if (arg == "--cell-mm") settings.surface_cell_mm = parseNumber(arg, value());
    else if (arg == "--metric-points") settings.metric_points = parseCount(arg, value(), 100000);
    else if (arg == "--global-shape") settings.global_shape_per_mm2 = parseNumber(arg, value());
    else if (arg == "--global-search") job.global_search = parseList(arg, value());
    else if (arg == "--fix-winding") job.fix_winding = true;
    else if (arg == "--out-of") job.out_of = parseFileList(arg, value());
    else if (arg == "--quiet") job.quiet = true;
    else if (!arg.empty() && arg[0] == '-') throw UsageError("fit: unknown option '" + arg + "'\n" + kFitUsage);
    else if (job.mesh_path.empty()) job.mesh_path = arg;
    else throw UsageError("fit: more than one mesh given ('" + job.mesh_path + "', '" + arg + "')");
  }
  if (job.mesh_path.empty()) throw UsageError(std::string("fit: no mesh given\n") + kFitUsage);
  if (require_output && job.output_path.empty())
    throw UsageError(std::string("fit: -o OUT.rbf is required\n") + kFitUsage);
  if (!(settings.clamp_mm > 0)) throw UsageError("fit: --clamp-mm must be > 0");
  if (!(settings.normal_offset_mm > 0)) throw UsageError("fit: --normal-offset-mm must be > 0");
  if (!(settings.regularisation_gamma >= 0 && settings.regularisation_gamma <= 1))
    throw UsageError("fit: --gamma must be in [0, 1]");
  if (!(settings.batch_fraction > 0 && settings.batch_fraction <= 1))
    throw UsageError("fit: --batch-fraction must be in (0, 1]");
  if (!(settings.surface_cell_mm > 0)) throw UsageError("fit: --cell-mm must be > 0");
  if (!(settings.check_start_fraction >= 0 && settings.check_start_fraction <= 1))
    throw UsageError("fit: --check-start must be in [0, 1]");
  if (!(settings.check_slope >= 0 && settings.check_slope <= 1))
    throw UsageError("fit: --check-slope must be in [0, 1]");
  if (!(settings.crumb_margin_mm >= 0)) throw UsageError("fit: --crumb-margin-mm must be ≥ 0");
  if (!job.global_search.empty() && job.global_search.size() != 3)
    throw UsageError("fit: --global-search expects LO,HI,K");
  // K full fits; beyond 100 the golden-section bracket has long stopped shrinking in double precision.
  const double fits = job.global_search.empty() ? 2.0 : job.global_search[2];
  if (!(fits >= 2 && fits <= 100 && fits == std::floor(fits)))
    throw UsageError("fit: --global-search LO,HI,K: K is the number of fits, a whole number from 2 to 100");
  return job;
}

MeshFit runFitJob(const FitJob& job, const FitProgressFn& progress,
                  const std::function<void(double alpha, double metric)>& global_report) {
  // An output never replaces an input or another output (the same file by device and inode,
  // or the same path when it does not exist yet).
  if (!job.output_path.empty() && io::isSameFile(job.output_path, job.mesh_path))
    throw UsageError("fit: -o " + job.output_path + " is the input mesh " + job.mesh_path +
                     "; refusing to overwrite it (choose another output file)");
  if (!job.surface_path.empty() && io::isSameFile(job.surface_path, job.mesh_path))
    throw UsageError("fit: --surface " + job.surface_path + " is the input mesh " + job.mesh_path +
                     "; refusing to overwrite it (choose another output file)");
  if (!job.surface_path.empty() && !job.output_path.empty() && io::isSameFile(job.surface_path, job.output_path))
    throw UsageError("fit: --surface " + job.surface_path + " and -o " + job.output_path +
                     " are the same file; give two different files");
  {
    const std::string problem = io::findInputFileProblem(job.mesh_path, "a mesh file");
    if (!problem.empty()) throw std::runtime_error(job.mesh_path + ": " + problem);
  }
  if (!job.output_path.empty()) checkWritable(job.output_path);
  if (!job.surface_path.empty()) checkWritable(job.surface_path);
  std::vector<std::unique_ptr<MeshDistance>> distances;
  std::vector<PlacedSolid> solids;
  for (const std::string& path : job.out_of) {
    distances.push_back(std::make_unique<MeshDistance>(loadSolidMesh(path)));
    solids.push_back(PlacedSolid{distances.back().get(), Eigen::Isometry3d::Identity(), path});
  }
  MeshAdjustFn move_out;
  if (!solids.empty())
    move_out = [&](TriangleMesh& mesh) {
      if (const std::string moved = describeMoveOut(job.mesh_path, moveOutOfSolids(mesh, solids)); !moved.empty())
        printMeshWarning(moved);
    };
  if (job.global_search.empty()) return fitMeshFile(job.mesh_path, job.settings, job.fix_winding, progress, move_out);
  return fitMeshFileGlobalShape(job.mesh_path, job.settings, job.fix_winding, job.global_search[0],
                                job.global_search[1], static_cast<int>(job.global_search[2]), global_report, move_out);
}

void writeFitOutputs(const FitJob& job, const MeshFit& fit) {
  if (!job.output_path.empty()) writeRbfFile(job.output_path, fit.surface);
  if (job.surface_path.empty()) return;
  try {
    writePly(job.surface_path, fittedSurfaceInSourceFrame(fit));
  } catch (...) {
    if (!job.output_path.empty()) std::remove(job.output_path.c_str());  // all outputs or none
    throw;
  }
}

TriangleMesh fittedSurfaceInSourceFrame(const MeshFit& fit) {
  TriangleMesh mesh = fit.metrics.surface_M;
  mesh.vertices_mm.colwise() += fit.surface.frame_offset_mm;
  return mesh;
}

int runFitCommand(int argc, char** argv) {
  const FitJob job = parseFitArguments(std::vector<std::string>(argv + 1, argv + argc), true);
  if (job.help) {
    std::fputs(kFitUsage, stdout);
    return 0;
  }
  const bool quiet = job.quiet;
  const FitProgressFn progress = [quiet](const FitProgress& p) {
    throwIfInterrupted();  // SIGINT / SIGTERM: stop after this round, nothing written
    if (quiet) return;
    std::fprintf(stderr, "\rfit: round %4d  centres %6d/%d  rms surface %.4f mm  rms all %.4f mm   ",
                 p.round, p.centres, p.max_centres, p.rms_surface_mm, p.rms_all_mm);
    std::fflush(stderr);
  };
  const MeshFit fit = runFitJob(job, progress, [quiet](double alpha, double metric) {
    if (!quiet) std::fprintf(stderr, "fit: global shape %.6g mm^-2 -> C_m %.6f\n", alpha, metric);
  });
  if (!quiet) std::fprintf(stderr, "\nfit: stopped by %s after %d rounds; last refit: %s after %d iterations; %d check points and %d "
                           "near crumbs (peaks and floors) made samples; %d samples resigned\n",
                           fit.stop_reason.c_str(), fit.rounds,
                           fit.final_refit.reached_tolerance ? "tolerance" : "iteration cap",
                           fit.final_refit.iterations, fit.check_samples_added, fit.near_crumb_samples_added,
                           fit.resigned_samples);
  for (const std::string& warning : fit.warnings) printMeshWarning(warning);
  writeFitOutputs(job, fit);
  std::cout << fit.surface.metrics_json << std::endl;
  return 0;
}

}  // namespace rbfmuscle
