// SPDX-License-Identifier: Apache-2.0
#include "framework/invariant.h"

#include "framework/component.h"

#include <cmath>
#include <sstream>

namespace rbfmuscle {
namespace {

bool holds(const Invariant& invariant, double value) {
  if (std::isnan(value)) return invariant.may_be_absent;
  return std::isfinite(value) && value >= invariant.min && value <= invariant.max;
}

}  // namespace

InvariantChecker::InvariantChecker(const std::vector<std::unique_ptr<Component>>& components, bool strict,
                                   std::function<void(const std::string&)> warn)
    : strict_(strict), warn_(std::move(warn)) {
  for (const auto& component : components)
    for (const Invariant& invariant : component->getInvariants()) {
      const AbstractOutput* output = component->findOutput(invariant.output);
      if (!output)
        throwAt(component->getSourceLocation(), "declares an invariant on output '" + invariant.output +
                                                    "', which it does not have (" + invariant.promise + ")");
      watched_.push_back({component.get(), &invariant, output});
    }
}

std::string InvariantChecker::describeBreak(const Component& component, const Invariant& invariant, double value,
                                            int element) {
  std::ostringstream text;
  text.precision(6);
  text << component.getName() << '.' << invariant.output;
  if (element >= 0) text << '_' << element;
  text << " = " << value << " breaks its invariant: " << invariant.promise << " (expected a finite value";
  if (std::isfinite(invariant.min) && std::isfinite(invariant.max))
    text << " from " << invariant.min << " to " << invariant.max;
  else if (std::isfinite(invariant.min))
    text << " of at least " << invariant.min;
  else if (std::isfinite(invariant.max))
    text << " of at most " << invariant.max;
  text << ')';
  return text.str();
}

void InvariantChecker::check(int frame, double time_s) {
  for (Watched& w : watched_) {
    values_.clear();
    w.output->appendValues(values_);
    int bad = -1;
    for (std::size_t i = 0; i < values_.size() && bad < 0; ++i)
      if (!holds(*w.invariant, values_[i])) bad = static_cast<int>(i);
    if (bad < 0) continue;
    const double value = values_[static_cast<std::size_t>(bad)];
    const int element = w.output->getSize() == 1 && std::string(w.output->getTypeName()) == "double" ? -1 : bad;
    std::ostringstream where;
    where << "frame " << frame << " (t = " << time_s << " s): ";
    const std::string what = where.str() + describeBreak(*w.component, *w.invariant, value, element);
    if (strict_) throwAt(w.component->getSourceLocation(), what + " [--strict]");
    if (w.broken < 0) {
      w.broken = static_cast<int>(breaks_.size());
      breaks_.push_back({w.component->getName(), w.invariant->output, w.invariant->promise, frame, 0});
      if (warn_)
        warn_(what + "; later frames that break it are counted, not shown");
    }
    ++breaks_[static_cast<std::size_t>(w.broken)].frames;
  }
}

}  // namespace rbfmuscle
