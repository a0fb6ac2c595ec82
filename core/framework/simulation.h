// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The run loop: initialize components, step through the motion, update each
/// component, record outputs, and write OUTDIR all-or-nothing:
///   OUTDIR/outputs.sto, OUTDIR/outputs.csv (see Reporter),
///   OUTDIR/summary.json (frames, wall time per frame, time per stage, median and
///   maximum of every recorded `*_ms` output, and the invariants broken),
///   OUTDIR/meshes/NAME_#####.vtp + OUTDIR/NAME.pvd with --frames-mesh.
#include "framework/invariant.h"
#include "framework/model.h"

#include <string>
#include <vector>

namespace rbfmuscle {

/// A component's initialisation that takes longer than this is announced on stderr (s).
inline constexpr double kSlowWorkFirstNoticeSeconds = 5.0;
/// ... and again every so many seconds until it ends (s).
inline constexpr double kSlowWorkNoticeSeconds = 30.0;

struct RunOptions {
  std::string output_directory;     ///< OUTDIR
  bool write_frame_meshes = false;  ///< --frames-mesh
  /// progress on stderr: a component initialisation or a first frame longer than
  /// kSlowWorkFirstNoticeSeconds is announced (and repeated every kSlowWorkNoticeSeconds), and
  /// the frame loop shows frame i/N with the estimated time left from the first frame on
  /// (ProgressBar)
  bool show_progress = true;
  double load_seconds = 0.0;        ///< time the caller spent loading plugins and model (reported)
  /// --strict: a frame that breaks an invariant a component declared (invariant.h) fails the
  /// run; otherwise each broken invariant is warned about once on stderr and counted.
  bool strict_invariants = false;
};

/// Wall time of one stage of the frame loop, over all frames.
struct StageTiming {
  std::string name;     ///< "skeleton", "component NAME (CLASS)", "output", "frames_mesh"
  double total_ms = 0;  ///< sum over frames
  double max_ms = 0;    ///< slowest frame
};

/// Median and maximum over the frames of a component's reported time (an output whose name
/// ends in `_ms`, e.g. `iliacus_r.prediction_ms`), over the frames where it is a number.
struct ReportedTiming {
  std::string output;  ///< COMPONENT.OUTPUT
  double median_ms = 0;
  double max_ms = 0;
};

struct RunSummary {
  int frames = 0;
  double initialize_seconds = 0;  ///< Component::initialize, all components
  double loop_seconds = 0;        ///< frame loop
  double total_seconds = 0;       ///< load + initialize + loop + writing files
  double frame_median_ms = 0;     ///< wall time of one frame (all stages)
  double frame_max_ms = 0;
  std::vector<StageTiming> stages;
  std::vector<ReportedTiming> reported;  ///< every recorded `*_ms` output, in column order
  std::vector<InvariantBreak> invariant_breaks;  ///< invariants broken (none under --strict)
};

/// Runs the model's motion: initialises the components, then steps a Session (session.h)
/// through the motion's frames.
/// @throws FrameworkError (or the component's exception text prefixed with its
///   XML location); OUTDIR is then neither created nor changed.
RunSummary runModel(Model& model, const RunOptions& options);

/// Writes summary.json for a finished run.
void writeSummaryJson(const std::string& path, const Model& model, const RunSummary& summary,
                      double load_seconds);

}  // namespace rbfmuscle
