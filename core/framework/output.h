// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Named outputs of a component, declared as members (as OpenSim's
/// OpenSim_DECLARE_OUTPUT). An output only reads the result struct that
/// update() filled; it computes nothing.
///
///     Output x_mm{this, "x_mm", "mm", "x of P in ground", [this] { return result_.p_GP_mm.x(); }};
///     VectorOutput fibre_length_mm{this, "fibre_length_mm", "mm", "length of each fibre",
///                                  [this]() -> const Eigen::VectorXd& { return result_.lengths_mm; }};
///
/// Reporter columns: `COMPONENT.OUTPUT` for a scalar, `COMPONENT.OUTPUT_i`
/// (i = 0..size-1) for each element of a vector output.
#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace rbfmuscle {

class Component;

/// Type-erased output.
class AbstractOutput {
 public:
  AbstractOutput(const AbstractOutput&) = delete;
  AbstractOutput& operator=(const AbstractOutput&) = delete;
  virtual ~AbstractOutput() = default;

  const std::string& getName() const { return name_; }
  /// Unit text, e.g. "mm", "rad", "1" for dimensionless.
  const std::string& getUnit() const { return unit_; }
  const std::string& getDescription() const { return description_; }
  /// "double" or "vector of double".
  virtual const char* getTypeName() const = 0;
  /// Number of values (1 for a scalar; a vector's size is fixed after initialize()).
  virtual int getSize() const = 0;
  /// Appends the current value(s) to `row`.
  virtual void appendValues(std::vector<double>& row) const = 0;

 protected:
  AbstractOutput(Component* owner, std::string name, std::string unit, std::string description);

 private:
  std::string name_;
  std::string unit_;
  std::string description_;
};

/// A scalar double output.
class Output final : public AbstractOutput {
 public:
  Output(Component* owner, std::string name, std::string unit, std::string description,
         std::function<double()> getter)
      : AbstractOutput(owner, std::move(name), std::move(unit), std::move(description)),
        getter_(std::move(getter)) {}
  double getValue() const { return getter_(); }
  const char* getTypeName() const override { return "double"; }
  int getSize() const override { return 1; }
  void appendValues(std::vector<double>& row) const override { row.push_back(getter_()); }

 private:
  std::function<double()> getter_;
};

/// A vector-of-doubles output (e.g. one value per fibre).
class VectorOutput final : public AbstractOutput {
 public:
  VectorOutput(Component* owner, std::string name, std::string unit, std::string description,
               std::function<const Eigen::VectorXd&()> getter)
      : AbstractOutput(owner, std::move(name), std::move(unit), std::move(description)),
        getter_(std::move(getter)) {}
  const Eigen::VectorXd& getValue() const { return getter_(); }
  const char* getTypeName() const override { return "vector of double"; }
  int getSize() const override { return static_cast<int>(getter_().size()); }
  void appendValues(std::vector<double>& row) const override {
    const Eigen::VectorXd& values = getter_();
    row.insert(row.end(), values.data(), values.data() + values.size());
  }

 private:
  std::function<const Eigen::VectorXd&()> getter_;
};

}  // namespace rbfmuscle
