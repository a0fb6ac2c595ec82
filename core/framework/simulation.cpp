// SPDX-License-Identifier: Apache-2.0
#include "framework/simulation.h"

#include "framework/interrupt.h"
#include "framework/progress_bar.h"
#include "framework/reporter.h"
#include "framework/session.h"
#include "framework/staged_directory.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

namespace rbfmuscle {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void addTime(StageTiming& stage, double ms) {
  stage.total_ms += ms;
  stage.max_ms = std::max(stage.max_ms, ms);
}

std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/// Median of a non-empty list (sorted in place).
double medianOf(std::vector<double>& values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// Median and maximum of every `*_ms` column of the recorded table (the components' own
/// timings, such as volume_ms), over its finite values; columns without one are left out.
std::vector<ReportedTiming> summarizeReportedTimes(const StorageTable& table) {
  std::vector<ReportedTiming> out;
  const std::string suffix = "_ms";
  for (std::size_t c = 1; c < table.column_labels.size(); ++c) {
    const std::string& label = table.column_labels[c];
    if (label.size() < suffix.size() || label.compare(label.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    std::vector<double> values;
    for (const std::vector<double>& row : table.rows)
      if (std::isfinite(row[c])) values.push_back(row[c]);
    if (values.empty()) continue;
    const double median = medianOf(values);
    out.push_back({label, median, values.back()});
  }
  return out;
}

/// Writes this frame's component geometry and records it in the .pvd series.
void writeFrameGeometry(const Model& model, int frame, double time_s, const std::string& dir,
                        std::vector<FrameGeometry>& buffer, std::map<std::string, PvdSeries>& series) {
  namespace fs = std::filesystem;
  for (const auto& component : model.getComponents()) {
    buffer.clear();
    component->appendFrameGeometry(buffer);
    for (const FrameGeometry& geometry : buffer) {
      char index[16];
      std::snprintf(index, sizeof index, "_%05d.vtp", frame);
      const std::string file = "meshes/" + geometry.name + index;
      writeVtp((fs::path(dir) / file).string(), geometry);
      series[geometry.name].add(time_s, file);
    }
  }
}

/// Tells the user about one step that takes long: nothing while it is quick; after
/// kSlowWorkFirstNoticeSeconds a line "rbfmuscle: still <what>: N s so far", repeated every
/// kSlowWorkNoticeSeconds, and when it was announced, a closing line with its duration. A run
/// whose steps are all quick prints nothing, so an error stays the only line on stderr.
class SlowWorkNotice {
 public:
  explicit SlowWorkNotice(std::string what) : what_(std::move(what)), start_(Clock::now()) {
    thread_ = std::thread([this] { watch(); });
  }
  ~SlowWorkNotice() { stop(); }
  SlowWorkNotice(const SlowWorkNotice&) = delete;
  SlowWorkNotice& operator=(const SlowWorkNotice&) = delete;

  /// Ends the watch; prints "rbfmuscle: <done> in T s" when the step was announced.
  void finish(const std::string& done) {
    stop();
    if (announced_)
      std::fprintf(stderr, "rbfmuscle: %s in %.3g s\n", done.c_str(), msSince(start_) / 1000.0);
  }

 private:
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopped_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    double next_s = kSlowWorkFirstNoticeSeconds;
    while (!wake_.wait_for(lock, std::chrono::duration<double>(next_s) - (Clock::now() - start_),
                           [this] { return stopped_; })) {
      std::fprintf(stderr, "rbfmuscle: still %s: %.0f s so far\n", what_.c_str(), msSince(start_) / 1000.0);
      std::fflush(stderr);
      announced_ = true;
      next_s += kSlowWorkNoticeSeconds;
    }
  }

  std::string what_;
  Clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopped_ = false;
  bool announced_ = false;
  std::thread thread_;
};

/// Initialises the model's components (which may write into `dir`), announcing one that takes
/// long when progress is shown; returns the seconds taken.
double initializeComponentsTimed(Model& model, const std::string& dir, bool show_progress) {
  const auto start = Clock::now();
  std::unique_ptr<SlowWorkNotice> notice;
  model.initializeComponents(dir, [&](const Component& component, int index, int count, bool done) {
    if (!show_progress) return;
    const std::string what = component.getName() + " (" + component.getClassName() + "), component " +
                             std::to_string(index + 1) + " of " + std::to_string(count);
    if (!done) {
      notice = std::make_unique<SlowWorkNotice>("initialising " + what);
    } else if (notice) {
      notice->finish("initialised " + what);
      notice.reset();
    }
  });
  notice.reset();
  return msSince(start) / 1000.0;
}

/// The stages timed in each frame: the skeleton, each component, the output, and the frame
/// meshes when they are written.
std::vector<StageTiming> nameStages(const Model& model, bool write_frame_meshes) {
  std::vector<StageTiming> stages;
  stages.push_back({"skeleton"});
  for (const auto& component : model.getComponents())
    stages.push_back({"component " + component->getName() + " (" +
                      component->getClassName() + ")"});
  stages.push_back({"output"});
  if (write_frame_meshes) stages.push_back({"frames_mesh"});
  return stages;
}

/// Adds one frame's times to the stages named by nameStages.
void addFrameTiming(const FrameTiming& timing, std::size_t num_components, std::vector<StageTiming>& stages) {
  addTime(stages[0], timing.skeleton_ms);
  for (std::size_t c = 0; c < num_components; ++c) addTime(stages[1 + c], timing.component_ms[c]);
  addTime(stages[1 + num_components], timing.output_ms);
}

/// The median and maximum of the frames' wall times (ms), into `summary`.
void summarizeFrameTimes(const std::vector<double>& frame_ms, RunSummary& summary) {
  if (frame_ms.empty()) return;
  std::vector<double> sorted = frame_ms;
  summary.frame_median_ms = medianOf(sorted);
  summary.frame_max_ms = sorted.back();
}

/// Steps the session through every frame of the motion. Each stage's time goes to
/// summary.stages; the loop's wall time, the frames' median and maximum, and the broken
/// invariants (counted on stderr at the end) to `summary`. With options.write_frame_meshes, each frame's
/// geometry is written under `dir` and listed in `series`.
void runFrameLoop(const Model& model, Session& session, const RunOptions& options, const std::string& dir,
                  std::map<std::string, PvdSeries>& series, RunSummary& summary) {
  const Motion& motion = model.getMotion();
  const auto& components = model.getComponents();
  const int frames = motion.getNumFrames();
  std::vector<double> frame_ms;
  frame_ms.reserve(frames);
  std::vector<FrameGeometry> geometry_buffer;

  ProgressBar progress(frames, options.show_progress);
  const auto loop_start = Clock::now();
  for (int frame = 0; frame < frames; ++frame) {
    throwIfInterrupted();
    // The first frame may be slow (its cost is unknown until it ends): announce it if it is.
    std::unique_ptr<SlowWorkNotice> first_frame_notice;
    if (frame == 0 && options.show_progress)
      first_frame_notice = std::make_unique<SlowWorkNotice>("computing frame 1 of " + std::to_string(frames));
    const auto frame_start = Clock::now();
    const double time_s = motion.getTime(frame);
    const FrameTiming& timing = session.step(time_s, motion.getCoordinates(frame), options.write_frame_meshes);
    addFrameTiming(timing, components.size(), summary.stages);
    if (options.write_frame_meshes) {
      const auto meshes_start = Clock::now();
      writeFrameGeometry(model, frame, time_s, dir, geometry_buffer, series);
      addTime(summary.stages.back(), msSince(meshes_start));
    }
    frame_ms.push_back(msSince(frame_start));
    if (first_frame_notice) first_frame_notice->finish("computed frame 1 of " + std::to_string(frames));
    progress.update(frame + 1);
  }
  progress.finish();
  summary.invariant_breaks = session.getInvariantBreaks();
  for (const InvariantBreak& b : summary.invariant_breaks)
    std::fprintf(stderr, "rbfmuscle: warning: %s.%s broke its invariant (%s) in %d of %d frames, first at frame %d\n",
                 b.component.c_str(), b.output.c_str(), b.promise.c_str(), b.frames, frames, b.first_frame);
  summary.loop_seconds = msSince(loop_start) / 1000.0;
  summary.frames = frames;
  summarizeFrameTimes(frame_ms, summary);
}

}  // namespace

RunSummary runModel(Model& model, const RunOptions& options) {
  namespace fs = std::filesystem;
  const auto run_start = Clock::now();
  StagedDirectory outdir(options.output_directory);
  const std::string dir = outdir.getStagingPath();
  if (options.write_frame_meshes) fs::create_directory(fs::path(dir) / "meshes");

  RunSummary summary;
  summary.initialize_seconds = initializeComponentsTimed(model, dir, options.show_progress);

  Session session(model, model.getMotion().getNumFrames(), options.strict_invariants);
  summary.stages = nameStages(model, options.write_frame_meshes);
  std::map<std::string, PvdSeries> series;
  runFrameLoop(model, session, options, dir, series, summary);
  summary.reported = summarizeReportedTimes(session.getTable());

  session.getReporter().write(dir);
  for (const auto& [name, pvd] : series) pvd.write((fs::path(dir) / (name + ".pvd")).string());
  summary.total_seconds = options.load_seconds + msSince(run_start) / 1000.0;
  writeSummaryJson((fs::path(dir) / "summary.json").string(), model, summary, options.load_seconds);
  throwIfInterrupted();
  outdir.commit();
  return summary;
}

void writeSummaryJson(const std::string& path, const Model& model, const RunSummary& summary,
                      double load_seconds) {
  std::ofstream out(path);
  if (!out) throw FrameworkError("cannot write " + path);
  out.precision(6);
  const double fps = summary.loop_seconds > 0 ? summary.frames / summary.loop_seconds : 0.0;
  out << "{\n"
      << "  \"model\": " << jsonString(model.getDocument().name) << ",\n"
      << "  \"model_file\": " << jsonString(model.getDocument().path) << ",\n"
      << "  \"frames\": " << summary.frames << ",\n"
      << "  \"frames_per_second\": " << fps << ",\n"
      << "  \"frame_wall_ms\": {\"median\": " << summary.frame_median_ms
      << ", \"max\": " << summary.frame_max_ms << "},\n"
      << "  \"seconds\": {\"load\": " << load_seconds << ", \"initialize\": "
      << summary.initialize_seconds << ", \"frame_loop\": " << summary.loop_seconds
      << ", \"total\": " << summary.total_seconds << "},\n"
      << "  \"stages_ms\": [\n";
  for (std::size_t i = 0; i < summary.stages.size(); ++i) {
    const StageTiming& s = summary.stages[i];
    out << "    {\"stage\": " << jsonString(s.name) << ", \"total\": " << s.total_ms
        << ", \"mean_per_frame\": " << (summary.frames ? s.total_ms / summary.frames : 0.0)
        << ", \"max\": " << s.max_ms << "}" << (i + 1 < summary.stages.size() ? "," : "") << "\n";
  }
  out << "  ],\n"
      << "  \"reported_ms\": [\n";
  for (std::size_t i = 0; i < summary.reported.size(); ++i) {
    const ReportedTiming& r = summary.reported[i];
    out << "    {\"output\": " << jsonString(r.output) << ", \"median\": " << r.median_ms
        << ", \"max\": " << r.max_ms << "}" << (i + 1 < summary.reported.size() ? "," : "") << "\n";
  }
  out << "  ],\n"
      << "  \"invariants_broken\": [\n";
  for (std::size_t i = 0; i < summary.invariant_breaks.size(); ++i) {
    const InvariantBreak& b = summary.invariant_breaks[i];
    out << "    {\"output\": " << jsonString(b.component + "." + b.output) << ", \"promise\": " << jsonString(b.promise)
        << ", \"frames\": " << b.frames << ", \"first_frame\": " << b.first_frame << "}"
        << (i + 1 < summary.invariant_breaks.size() ? "," : "") << "\n";
  }
  out << "  ],\n"
      << "  \"machine\": {\"hardware_threads\": " << std::thread::hardware_concurrency()
      << ", \"note\": \"single-threaded frame loop; wall-clock times (steady_clock)\"}\n"
      << "}\n";
  if (!out) throw FrameworkError("cannot write " + path);
}

}  // namespace rbfmuscle
