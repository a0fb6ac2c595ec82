// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Invariants: promises a component makes about its own outputs, checked by the run loop after
/// every frame, so that a frame that breaks one is caught where it happens instead of in a
/// picture later. A component declares them (Component::declareInvariant) by output name and
/// bounds; the run loop knows no component class.
///
/// A run warns once per broken invariant (component and output), naming the frame, and counts
/// the frames that break it; under `rbfmuscle run --strict` the first break fails the run.
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace rbfmuscle {

class AbstractOutput;
class Component;

/// Every value of output `output` of the declaring component is finite and within [min, max].
struct Invariant {
  std::string output;                                       ///< name of an output of the component
  double min = -std::numeric_limits<double>::infinity();    ///< smallest value allowed
  double max = std::numeric_limits<double>::infinity();     ///< largest value allowed
  std::string promise;                                      ///< what it means, e.g. "volume within its tolerance"
  /// NaN means "not computed this frame" (e.g. a surface only tracked for pictures) and passes;
  /// ±∞ and values out of bounds still break the invariant. When false, NaN breaks it too.
  bool may_be_absent = false;
};

/// One invariant broken in a run: where first and how often.
struct InvariantBreak {
  std::string component;      ///< component name
  std::string output;         ///< output name
  std::string promise;
  int first_frame = 0;        ///< 0-based frame of the first break
  int frames = 0;             ///< frames that broke it
};

/// Checks every component's invariants against its outputs' current values.
class InvariantChecker {
 public:
  /// @param strict a break throws instead of warning
  /// @param warn   receives each warning line (without a trailing newline)
  /// @throws FrameworkError (at the component's XML location) when an invariant names an
  ///   output the component does not have.
  InvariantChecker(const std::vector<std::unique_ptr<Component>>& components, bool strict,
                   std::function<void(const std::string&)> warn);

  /// Checks the values after `frame`'s update. Warns once per invariant (its first break);
  /// @throws FrameworkError (at the component's XML location) on a break when strict.
  void check(int frame, double time_s);

  /// Every invariant broken so far, in the order of their first break.
  const std::vector<InvariantBreak>& getBreaks() const { return breaks_; }

  /// "component.output = value breaks its invariant: promise (expected …)", for messages.
  static std::string describeBreak(const Component& component, const Invariant& invariant, double value, int element);

 private:
  struct Watched {
    const Component* component;
    const Invariant* invariant;
    const AbstractOutput* output;
    int broken = -1;  ///< index into breaks_, -1 while it holds
  };
  std::vector<Watched> watched_;
  std::vector<InvariantBreak> breaks_;
  std::vector<double> values_;  ///< reused per output
  bool strict_;
  std::function<void(const std::string&)> warn_;
};

}  // namespace rbfmuscle
