#include "host/fit_command.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "fit/fit_pipeline.h"
#include "framework/interrupt.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_warning.h"
#include "host_commands.h"
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
    "  --clamp-mm TAU          clamp of the signed-distance target [10]\n"
    "  --normal-offset-mm D    samples ±D along vertex normals [1]\n"
    "  --halton N              Halton samples in the padded box [30000]\n"
    "  --check-band N          check points within the clamp of the surface [30000]\n"
    "  --no-check-layers       no check points 2D, 4D, 8D … (< TAU) off the vertices along their normals\n"
    "  --check-start F         checks begin at this fraction of the centre budget [0.75]\n"
    "  --shapes A,B,...        shape set α in mm^-2 [0.005 … 0.5]\n"
    "  --gamma G               regularisation γ of eq. 7.12, 1 = none [0.9]\n"
    "  --batch-fraction F      centres added per round / current count [0.1]\n"
    "  --cell-mm H             grid cell of the extracted surface [1]\n"
    "  --metric-points N       points for the Jaccard index (≥ 100000) [200000]\n"
    "  --global-shape ALPHA    one shape α for every centre\n"
    "  --global-search LO,HI,K search the best global α in [LO, HI] with K fits (golden section)\n"
    "  --fix-winding           rewind inconsistently wound triangles instead of failing\n"
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

/// Surface mesh back in the source mesh's frame.
TriangleMesh toSourceFrame(TriangleMesh mesh, const Eigen::Vector3d& offset_mm) {
  mesh.vertices_mm.colwise() += offset_mm;
  return mesh;
}

}  // namespace

int runFitCommand(int argc, char** argv) {
  std::string mesh_path, output_path, surface_path;
  FitSettings settings;
  bool fix_winding = false, quiet = false;
  std::vector<double> search;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError("fit: " + arg + " needs a value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kFitUsage, stdout);
      return 0;
    } else if (arg == "--centres") settings.max_centres = parseCount(arg, value(), 1);
    else if (arg == "-o" || arg == "--output") output_path = value();
    else if (arg == "--surface") surface_path = value();
    else if (arg == "--tolerance-mm") settings.tolerance_mm = parseNumber(arg, value());
    else if (arg == "--clamp-mm") settings.clamp_mm = parseNumber(arg, value());
    else if (arg == "--normal-offset-mm") settings.normal_offset_mm = parseNumber(arg, value());
    else if (arg == "--halton") settings.halton_samples = parseCount(arg, value(), 0);
    else if (arg == "--check-band") settings.check_band_samples = parseCount(arg, value(), 0);
    else if (arg == "--check-start") settings.check_start_fraction = parseNumber(arg, value());
    else if (arg == "--no-check-layers") settings.check_normal_layers = false;
    else if (arg == "--shapes") settings.shapes_per_mm2 = parseList(arg, value());
    else if (arg == "--gamma") settings.regularisation_gamma = parseNumber(arg, value());
    else if (arg == "--batch-fraction") settings.batch_fraction = parseNumber(arg, value());
    else if (arg == "--cell-mm") settings.surface_cell_mm = parseNumber(arg, value());
    else if (arg == "--metric-points") settings.metric_points = parseCount(arg, value(), 100000);
    else if (arg == "--global-shape") settings.global_shape_per_mm2 = parseNumber(arg, value());
    else if (arg == "--global-search") search = parseList(arg, value());
    else if (arg == "--fix-winding") fix_winding = true;
    else if (arg == "--quiet") quiet = true;
    else if (!arg.empty() && arg[0] == '-') throw UsageError("fit: unknown option '" + arg + "'\n" + kFitUsage);
    else if (mesh_path.empty()) mesh_path = arg;
    else throw UsageError("fit: more than one mesh given ('" + mesh_path + "', '" + arg + "')");
  }
  if (mesh_path.empty()) throw UsageError(std::string("fit: no mesh given\n") + kFitUsage);
  if (output_path.empty()) throw UsageError(std::string("fit: -o OUT.rbf is required\n") + kFitUsage);
  if (!(settings.clamp_mm > 0)) throw UsageError("fit: --clamp-mm must be > 0");
  if (!(settings.normal_offset_mm > 0)) throw UsageError("fit: --normal-offset-mm must be > 0");
  if (!(settings.regularisation_gamma >= 0 && settings.regularisation_gamma <= 1))
    throw UsageError("fit: --gamma must be in [0, 1]");
  if (!(settings.batch_fraction > 0 && settings.batch_fraction <= 1))
    throw UsageError("fit: --batch-fraction must be in (0, 1]");
  if (!(settings.surface_cell_mm > 0)) throw UsageError("fit: --cell-mm must be > 0");
  if (!(settings.check_start_fraction >= 0 && settings.check_start_fraction <= 1))
    throw UsageError("fit: --check-start must be in [0, 1]");
  if (!search.empty() && search.size() != 3)
    throw UsageError("fit: --global-search expects LO,HI,K");
  // An output never replaces an input or another output (the same file by device and inode,
  // or the same path when it does not exist yet).
  if (io::isSameFile(output_path, mesh_path))
    throw UsageError("fit: -o " + output_path + " is the input mesh " + mesh_path +
                     "; refusing to overwrite it (choose another output file)");
  if (!surface_path.empty() && io::isSameFile(surface_path, mesh_path))
    throw UsageError("fit: --surface " + surface_path + " is the input mesh " + mesh_path +
                     "; refusing to overwrite it (choose another output file)");
  if (!surface_path.empty() && io::isSameFile(surface_path, output_path))
    throw UsageError("fit: --surface " + surface_path + " and -o " + output_path +
                     " are the same file; give two different files");
  {
    const std::string problem = io::findInputFileProblem(mesh_path, "a mesh file");
    if (!problem.empty()) throw std::runtime_error(mesh_path + ": " + problem);
  }
  checkWritable(output_path);
  if (!surface_path.empty()) checkWritable(surface_path);

  const FitProgressFn progress = [quiet](const FitProgress& p) {
    throwIfInterrupted();  // SIGINT / SIGTERM: stop after this round, nothing written
    if (quiet) return;
    std::fprintf(stderr, "\rfit: round %4d  centres %6d/%d  rms surface %.4f mm  rms all %.4f mm   ",
                 p.round, p.centres, p.max_centres, p.rms_surface_mm, p.rms_all_mm);
    std::fflush(stderr);
  };
  MeshFit fit;
  if (search.empty()) {
    fit = fitMeshFile(mesh_path, settings, fix_winding, progress);
  } else {
    fit = fitMeshFileGlobalShape(mesh_path, settings, fix_winding, search[0], search[1],
                                 static_cast<int>(search[2]), [quiet](double alpha, double metric) {
                                   if (!quiet) std::fprintf(stderr, "fit: global shape %.6g mm^-2 -> C_m %.6f\n", alpha, metric);
                                 });
  }
  if (!quiet) std::fprintf(stderr, "\nfit: stopped by %s after %d rounds; last refit: %s after %d iterations; %d check points made samples; %d samples resigned\n",
                           fit.stop_reason.c_str(), fit.rounds,
                           fit.final_refit.reached_tolerance ? "tolerance" : "iteration cap",
                           fit.final_refit.iterations, fit.check_samples_added, fit.resigned_samples);
  for (const std::string& warning : fit.warnings) printMeshWarning(warning);
  writeRbfFile(output_path, fit.surface);
  if (!surface_path.empty()) {
    try {
      writePly(surface_path, toSourceFrame(fit.metrics.surface_M, fit.surface.frame_offset_mm));
    } catch (...) {
      std::remove(output_path.c_str());  // all outputs or none
      throw;
    }
  }
  std::cout << fit.surface.metrics_json << std::endl;
  return 0;
}

}  // namespace rbfmuscle
