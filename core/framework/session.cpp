// SPDX-License-Identifier: Apache-2.0
#include "framework/session.h"

#include "framework/interrupt.h"

#include <chrono>
#include <cstdio>
#include <string>

namespace rbfmuscle {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

Session::Session(Model& model, int expected_frames, bool strict_invariants)
    : model_(model),
      reporter_(model.getDocument().name, model.getSkeleton().getCoordinateNames(), model.getComponents(),
                model.getDocument().reporter_patterns, model.getDocument().reporter_location, expected_frames),
      invariants_(model.getComponents(), strict_invariants, [](const std::string& line) {
        std::fprintf(stderr, "rbfmuscle: warning: %s\n", line.c_str());
        std::fflush(stderr);
      }) {
  const std::size_t bodies = model.getSkeleton().getBodyNames().size();
  X_GB_.assign(bodies, Eigen::Isometry3d::Identity());
  moved_.assign(bodies, 1);
  timing_.component_ms.assign(model.getComponents().size(), 0.0);
}

const FrameTiming& Session::step(double time_s, const Eigen::VectorXd& q, bool wants_geometry) {
  Skeleton& skeleton = model_.updSkeleton();
  const auto& components = model_.getComponents();
  has_geometry_ = false;
  auto start = Clock::now();
  skeleton.setCoordinateValues(q);
  for (std::size_t b = 0; b < X_GB_.size(); ++b) {
    const Eigen::Isometry3d X = skeleton.getBodyTransform(static_cast<int>(b));
    moved_[b] = recompute_all_ || !X.isApprox(X_GB_[b], 0.0);
    X_GB_[b] = X;
  }
  timing_.skeleton_ms = msSince(start);
  // A frame that fails leaves the components part-updated: the next one recomputes them all.
  recompute_all_ = true;
  const FrameState state(frames_, time_s, skeleton.getCoordinateValues(), X_GB_, moved_, wants_geometry);
  throwIfInterrupted();
  // Components of one frame are independent: they update in parallel, each as one task whose
  // per-point loops idle threads share (rbf/parallel_blocks.h), so the results do not depend on
  // the thread count. The first error (in document order) is the one reported.
  const int count = static_cast<int>(components.size());
  std::vector<std::string> errors(components.size());
#pragma omp parallel
#pragma omp single
  for (int c = 0; c < count; ++c) {
#pragma omp task firstprivate(c) shared(components, errors, state)
    {
      const auto component_start = Clock::now();
      const std::size_t i = static_cast<std::size_t>(c);
      try {
        components[i]->update(state);
      } catch (const std::exception& error) {
        errors[i] = error.what();
        if (errors[i].empty()) errors[i] = "unknown error";
      }
      timing_.component_ms[i] = msSince(component_start);
    }
  }
  for (std::size_t c = 0; c < components.size(); ++c)
    if (!errors[c].empty())
      throwAt(components[c]->getSourceLocation(), "update at frame " + std::to_string(frames_) + ": " + errors[c]);
  invariants_.check(frames_, time_s);
  start = Clock::now();
  reporter_.record(time_s, skeleton.getCoordinateValues());
  timing_.output_ms = msSince(start);
  recompute_all_ = false;
  has_geometry_ = wants_geometry;
  ++frames_;
  return timing_;
}

}  // namespace rbfmuscle
