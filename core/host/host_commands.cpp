// SPDX-License-Identifier: Apache-2.0
#include "host_commands.h"

#include "framework/model.h"
#include "framework/model_document.h"
#include "framework/plugin_loader.h"
#include "framework/registry.h"
#include "framework/simulation.h"
#include "host/model_loading.h"
#include "io/file_checks.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

const char* const kRunHelp =
    "usage: rbfmuscle run MODEL.xml -o OUTDIR [-L PLUGIN]... [--set C.P=V]... [--motion FILE]\n"
    "                     [--report C.OUTPUT]...\n"
    "                     [--frames-mesh] [--strict] [--quiet] [--keep-partial]\n"
    "\n"
    "Loads the plugins, builds the model from MODEL.xml, steps through its motion\n"
    "and writes, all or nothing (a failed run leaves OUTDIR untouched):\n"
    "  OUTDIR/outputs.sto, outputs.csv  time (s), every coordinate (rad), reported outputs\n"
    "  OUTDIR/summary.json              frames, wall time per frame and per stage, and\n"
    "                                   median and max of each reported *_ms output\n"
    "  OUTDIR/NAME.pvd, meshes/*.vtp    per-frame component geometry (--frames-mesh)\n"
    "An existing OUTDIR is replaced only when it is an earlier rbfmuscle output, and\n"
    "never when it holds the model, its directory, the skeleton or the motion.\n"
    "\n"
    "options:\n"
    "  -o, --output OUTDIR  output directory (required)\n"
    "  -L, --library PLUGIN load a component plugin (repeatable); see 'plugins' below\n"
    "  --set COMPONENT[/SUBCOMPONENT].PROPERTY=VALUE\n"
    "                       override (or add) a property of a component in MODEL.xml\n"
    "                       (repeatable; later ones win), e.g. --set glmax_r.centres=2000\n"
    "                       or --set glmax_r/fibres.count=50 (also glmax_r.fibres/count=50,\n"
    "                       as 'rbfmuscle info' lists it)\n"
    "  --motion FILE        use this motion file instead of MODEL.xml's (path relative to\n"
    "                       the current directory)\n"
    "  --report C.OUTPUT    record only the outputs matching this pattern ('*' matches any\n"
    "                       run of characters; repeatable), instead of the model's <reporter>\n"
    "  --frames-mesh        write each component's geometry per frame\n"
    "  --strict             fail the run (exit 1, OUTDIR untouched) at the first frame that\n"
    "                       breaks an invariant a component promises (e.g. a muscle's volume\n"
    "                       within its tolerance, finite outputs); without it each broken\n"
    "                       invariant is warned about once, with its frame, and counted\n"
    "  --quiet              no progress on stderr\n"
    "  --keep-partial       when stopped by SIGINT (Ctrl-C) or SIGTERM, keep OUTDIR.partial-PID\n"
    "                       (by default it is removed; the exit code is 130 or 143)\n"
    "  -h, --help           this text\n";

const char* const kInfoHelp =
    "usage: rbfmuscle info [-L PLUGIN]... [CLASS]\n"
    "\n"
    "Lists the registered component classes with their properties (type, default,\n"
    "range, unit and meaning), sockets and outputs; only CLASS when given.\n"
    "\n"
    "options:\n"
    "  -L, --library PLUGIN load a component plugin (repeatable)\n"
    "  -h, --help           this text\n";

const char* const kPluginHelp =
    "plugins: PLUGIN (from -L or <plugin file=...> in the model) is tried as given,\n"
    "then relative to the model file's directory, then in the host's ../lib directory;\n"
    "a bare name such as 'rbfmuscle_testplugin' is also tried as librbfmuscle_testplugin.so.\n";

/// Directory `../lib` next to the running executable ("" when unknown).
std::string hostLibraryDirectory() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  return (exe.parent_path().parent_path() / "lib").string();
}

struct CommandLine {
  std::vector<std::string> positional;
  std::vector<std::string> plugins;
  std::string output;
  std::vector<std::string> overrides;  ///< --set COMPONENT.PROPERTY=VALUE, in order
  std::string motion;                  ///< --motion FILE ("" = the model's)
  std::vector<std::string> reports;    ///< --report PATTERN, in order (empty = the model's)
  bool frames_mesh = false;
  bool strict = false;
  bool quiet = false;
  bool help = false;
};

/// Parses the options of `run` (with_run = true) or `info`.
CommandLine parseCommandLine(const std::vector<std::string>& args, bool with_run) {
  CommandLine line;
  std::set<std::string> given;  // options of one value: a second would silently replace the first
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw UsageError("option " + a + " needs a value");
      return args[++i];
    };
    auto once = [&](const std::string& option) {
      if (!given.insert(option).second) throw UsageError("option " + option + " is given twice");
    };
    if (a == "-h" || a == "--help") {
      line.help = true;
    } else if (a == "-L" || a == "--library") {
      line.plugins.push_back(value());
    } else if (a.size() > 2 && a.compare(0, 2, "-L") == 0) {
      line.plugins.push_back(a.substr(2));
    } else if (with_run && (a == "-o" || a == "--output")) {
      once("-o");
      line.output = value();
    } else if (with_run && a == "--set") {
      line.overrides.push_back(value());
    } else if (with_run && a == "--motion") {
      once(a);
      line.motion = value();
    } else if (with_run && a == "--report") {
      line.reports.push_back(value());
    } else if (with_run && a == "--frames-mesh") {
      line.frames_mesh = true;
    } else if (with_run && a == "--strict") {
      line.strict = true;
    } else if (with_run && a == "--quiet") {
      line.quiet = true;
    } else if (with_run && a == "--keep-partial") {
      // read by main() before any thread starts (installInterruptHandling)
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option '" + a + "'");
    } else {
      line.positional.push_back(a);
    }
  }
  return line;
}

}  // namespace

std::string usageText() {
  return std::string(
             "usage: rbfmuscle COMMAND [OPTIONS]\n"
             "\n"
             "commands:\n"
             "  run MODEL.xml -o OUTDIR [-L PLUGIN]... [--set C.P=V]... run a model's motion\n"
             "  info [-L PLUGIN]... [CLASS]                            list component types\n") +
#ifdef RBFMUSCLE_HAVE_FIT
         "  fit ...                                                fit a muscle surface\n" +
#endif
         "\n'rbfmuscle COMMAND --help' describes a command.\n";
}

int runCommand(const std::vector<std::string>& args) {
  const CommandLine line = parseCommandLine(args, true);
  if (line.help) {
    std::cout << kRunHelp << '\n' << kPluginHelp;
    return 0;
  }
  if (line.positional.size() != 1)
    throw UsageError("run needs exactly one MODEL.xml (got " +
                     std::to_string(line.positional.size()) + ")");
  if (line.output.empty()) throw UsageError("run needs -o OUTDIR");

  const auto start = std::chrono::steady_clock::now();
  Registry registry;
  PluginLoader loader;
  const ModelSource source{line.positional[0], line.plugins, line.overrides, line.motion, line.reports};
  ModelDocument document = readModelSource(source);
  // OUTDIR is replaced as a whole when the run succeeds: it may not hold an input.
  const std::pair<const char*, std::string> inputs[] = {{"model file", document.path},
                                                         {"model directory", document.directory},
                                                         {"skeleton", document.skeleton.path},
                                                         {"motion", document.motion.path}};
  for (const auto& [what, path] : inputs)
    if (io::isSameOrInside(path, line.output))
      throw UsageError("run: -o " + line.output + " holds the " + what + " " + path +
                       "; OUTDIR is replaced as a whole, so it may not hold an input (choose another OUTDIR)");
  Model model = buildModel(std::move(document), line.plugins, hostLibraryDirectory(), loader, registry);
  RunOptions options;
  options.output_directory = line.output;
  options.write_frame_meshes = line.frames_mesh;
  options.show_progress = !line.quiet;
  options.strict_invariants = line.strict;
  options.load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const RunSummary summary = runModel(model, options);
  std::fprintf(stderr,
               "rbfmuscle: %d frames in %.4g s (%.4g frames/s; frame median %.4g ms, max %.4g ms) "
               "-> %s\n",
               summary.frames, summary.loop_seconds,
               summary.loop_seconds > 0 ? summary.frames / summary.loop_seconds : 0.0,
               summary.frame_median_ms, summary.frame_max_ms, line.output.c_str());
  return 0;
}

int infoCommand(const std::vector<std::string>& args) {
  const CommandLine line = parseCommandLine(args, false);
  if (line.help) {
    std::cout << kInfoHelp << '\n' << kPluginHelp;
    return 0;
  }
  if (line.positional.size() > 1) throw UsageError("info takes at most one CLASS");
  Registry registry;
  PluginLoader loader;
  loadPlugins(line.plugins, "", hostLibraryDirectory(), loader, registry);
  if (line.positional.size() == 1) {
    const ComponentType* type = registry.findType(line.positional[0]);
    if (type == nullptr)
      throw FrameworkError("unknown component class '" + line.positional[0] +
                           "' (registered: " + registry.listTypeNames() + ")");
    std::cout << registry.describeType(*type);
    return 0;
  }
  std::cout << "Registered component types (" << registry.getTypes().size() << "):\n";
  if (registry.getTypes().empty())
    std::cout << "  none; load a plugin with -L PLUGIN\n";
  for (const ComponentType& type : registry.getTypes()) std::cout << '\n' << registry.describeType(type);
  return 0;
}

}  // namespace rbfmuscle
