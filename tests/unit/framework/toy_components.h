// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Toy components for the framework unit tests: every property type, every
/// socket kind, scalar and vector outputs.
#include "framework/component.h"
#include "framework/registry.h"
#include "framework/subcomponent.h"

#include <Eigen/Core>

namespace rbfmuscle::test {

/// All property types; `stiffness` in [0, 10]; `label` required.
class ToyComponent final : public Component {
 public:
  Property<double> stiffness{this, "stiffness", 2.5, "toy stiffness (N/mm)", PropertyRange{0.0, 10.0}};
  Property<int> count{this, "count", 3, "number of values in `values`", PropertyRange{1, 100}};
  Property<bool> enabled{this, "enabled", true, "whether update does anything"};
  Property<std::string> label{this, "label", "required label"};
  Property<Eigen::Vector3d> offset_mm{this, "offset_mm", Eigen::Vector3d(1, 2, 3), "offset (mm)"};
  BodySocket body{this, "body", "body read each frame"};
  Output sum{this, "sum", "1", "frame index + stiffness", [this] { return sum_; }};
  VectorOutput values{this, "values", "mm", "count values",
                      [this]() -> const Eigen::VectorXd& { return values_; }};

  void extendFinalizeProperties() override { values_ = Eigen::VectorXd::Zero(count.get()); }
  void update(const FrameState& state) override {
    sum_ = state.getFrameIndex() + stiffness.get();
    values_.setConstant(state.getBodyTransform(body).translation().x());
  }

 private:
  double sum_ = 0;
  Eigen::VectorXd values_;
};

/// Reads a ToyComponent through a component socket.
class ToyReader final : public Component {
 public:
  ComponentSocket<ToyComponent> source{this, "source", "ToyComponent", "component read"};
  BodyListSocket bodies{this, "bodies", "bodies watched"};
  Output twice_sum{this, "twice_sum", "1", "2 × source.sum", [this] { return value_; }};
  void update(const FrameState&) override { value_ = 2 * source.get().sum.getValue(); }

 private:
  double value_ = 0;
};

/// Settings of a ToyFiltered, as a subcomponent `<filter>`.
class ToyFilterSettings final : public Subcomponent {
 public:
  explicit ToyFilterSettings(Component* owner) : Subcomponent(owner, "filter", "toy low-pass filter") {}
  Property<int> order{this, "order", 2, "filter order", PropertyRange{1, 4}};
  Property<double> cutoff_hz{this, "cutoff_hz", 6.0, "cut-off frequency (Hz)"};
};

/// A component with one property and a subcomponent.
class ToyFiltered final : public Component {
 public:
  Property<double> gain{this, "gain", 1.0, "gain"};
  ToyFilterSettings filter{this};
  void update(const FrameState&) override {}
};

inline void registerToyTypes(Registry& registry) {
  registry.addType<ToyComponent>("ToyComponent", "toy with every property type");
  registry.addType<ToyReader>("ToyReader", "reads a ToyComponent");
}

}  // namespace rbfmuscle::test
