// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Typed component properties, declared as members at the top of a component
/// class (as OpenSim's OpenSim_DECLARE_PROPERTY) and read from XML child
/// elements of the same (snake_case) name.
///
///     Property<double> alpha_per_mm2{this, "alpha_per_mm2", 0.01,
///         "Gaussian shape α (mm⁻²)", PropertyRange{0.0, 1.0}};
///     Property<std::string> mesh_file{this, "mesh_file", "rest mesh, PLY in mm"};  // required
#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

namespace rbfmuscle {

class Component;

/// Closed interval [min, max] allowed for a double or int property.
struct PropertyRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
};

/// Type-erased property: what the framework needs to read, check and list it.
class AbstractProperty {
 public:
  AbstractProperty(const AbstractProperty&) = delete;
  AbstractProperty& operator=(const AbstractProperty&) = delete;
  virtual ~AbstractProperty() = default;

  const std::string& getName() const { return name_; }
  /// Meaning, with unit and frame, e.g. "point P fixed in the body, p_BP (mm)".
  const std::string& getDescription() const { return description_; }
  /// "double", "int", "bool", "string" or "Vector3".
  virtual const char* getTypeName() const = 0;
  /// True when the property has no default and must be given in the XML.
  bool isRequired() const { return required_; }
  /// True when a value is present (default, XML or set()).
  bool hasValue() const { return has_value_; }
  /// True when the value was read from the XML file.
  bool wasRead() const { return was_read_; }
  /// The default value as XML text ("" for a required property).
  virtual std::string formatDefault() const = 0;
  /// The current value as XML text.
  virtual std::string formatValue() const = 0;
  /// The allowed range as text ("" when unrestricted).
  std::string formatRange() const;

  /// Parses XML text into the value.
  /// @throws FrameworkError "expected a number, got 'abc'" (no location: the
  ///   caller prefixes file, line and element).
  void read(const std::string& text);
  /// Checks presence and range. @throws FrameworkError "property 'NAME': ...".
  void validate() const;

 protected:
  AbstractProperty(Component* owner, std::string name, std::string description, bool required,
                   PropertyRange range);
  virtual void parse(const std::string& text) = 0;
  /// The value as a number for the range check (NaN for non-numeric types).
  virtual double numericValue() const = 0;
  /// Non-finite numbers are rejected for numeric types and Vector3.
  virtual bool isFinite() const = 0;
  void markSet() { has_value_ = true; }

  PropertyRange range_;

 private:
  std::string name_;
  std::string description_;
  bool required_ = false;
  bool has_value_ = false;
  bool was_read_ = false;
};

/// Text conversion of the supported property types; parse functions throw
/// FrameworkError naming the expected type and the text found.
void parsePropertyText(const std::string& text, double& value);
void parsePropertyText(const std::string& text, int& value);
void parsePropertyText(const std::string& text, bool& value);
void parsePropertyText(const std::string& text, std::string& value);
void parsePropertyText(const std::string& text, Eigen::Vector3d& value);
std::string formatPropertyValue(double value);
std::string formatPropertyValue(int value);
std::string formatPropertyValue(bool value);
std::string formatPropertyValue(const std::string& value);
std::string formatPropertyValue(const Eigen::Vector3d& value);

template <class T> struct PropertyTypeName;
template <> struct PropertyTypeName<double> { static constexpr const char* value = "double"; };
template <> struct PropertyTypeName<int> { static constexpr const char* value = "int"; };
template <> struct PropertyTypeName<bool> { static constexpr const char* value = "bool"; };
template <> struct PropertyTypeName<std::string> { static constexpr const char* value = "string"; };
template <> struct PropertyTypeName<Eigen::Vector3d> { static constexpr const char* value = "Vector3"; };

/// A property of type T (double, int, bool, std::string or Eigen::Vector3d).
/// Registers itself with its owning component on construction.
template <class T>
class Property final : public AbstractProperty {
 public:
  /// Optional property with a default value; `range` applies to double/int.
  Property(Component* owner, std::string name, T default_value, std::string description,
           PropertyRange range = {})
      : AbstractProperty(owner, std::move(name), std::move(description), false, range),
        default_(default_value), value_(std::move(default_value)) {
    markSet();
  }
  /// Required property: no default; finalize fails when the XML omits it.
  Property(Component* owner, std::string name, std::string description, PropertyRange range = {})
      : AbstractProperty(owner, std::move(name), std::move(description), true, range),
        default_(), value_() {}

  const T& get() const { return value_; }
  void set(T value) {
    value_ = std::move(value);
    markSet();
  }
  const char* getTypeName() const override { return PropertyTypeName<T>::value; }
  std::string formatDefault() const override {
    return isRequired() ? std::string() : formatPropertyValue(default_);
  }
  std::string formatValue() const override { return formatPropertyValue(value_); }

 private:
  void parse(const std::string& text) override {
    T parsed{};
    parsePropertyText(text, parsed);
    value_ = std::move(parsed);
  }
  double numericValue() const override {
    if constexpr (std::is_same_v<T, double> || std::is_same_v<T, int>) {
      return static_cast<double>(value_);
    } else {
      return std::numeric_limits<double>::quiet_NaN();
    }
  }
  bool isFinite() const override {
    if constexpr (std::is_same_v<T, double>) {
      return std::isfinite(value_);
    } else if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
      return value_.allFinite();
    } else {
      return true;
    }
  }

  T default_;
  T value_;
};

}  // namespace rbfmuscle
