// SPDX-License-Identifier: Apache-2.0
#include "framework/property.h"

#include "framework/component.h"
#include "framework/framework_error.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace rbfmuscle {
namespace {

std::string trimmed(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return {};
  const auto end = text.find_last_not_of(" \t\r\n");
  return text.substr(begin, end - begin + 1);
}

/// Parses one whole token as a double; false when it is not a number.
bool parseDoubleToken(const std::string& token, double& value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size() && errno != ERANGE;
}

std::string formatDouble(double value) {
  std::ostringstream s;
  s.precision(17);
  s << value;
  return s.str();
}

}  // namespace

AbstractProperty::AbstractProperty(Component* owner, std::string name, std::string description,
                                   bool required, PropertyRange range)
    : range_(range), name_(std::move(name)), description_(std::move(description)),
      required_(required) {
  owner->properties_.push_back(this);
}

std::string AbstractProperty::formatRange() const {
  if (std::isinf(range_.min) && std::isinf(range_.max)) return {};
  return "[" + (std::isinf(range_.min) ? std::string("-inf") : formatDouble(range_.min)) + ", " +
         (std::isinf(range_.max) ? std::string("inf") : formatDouble(range_.max)) + "]";
}

void AbstractProperty::read(const std::string& text) {
  parse(text);
  has_value_ = true;
  was_read_ = true;
}

void AbstractProperty::validate() const {
  if (!has_value_)
    throw FrameworkError("property '" + name_ + "' (" + getTypeName() +
                         ") is required: expected a <" + name_ + "> element");
  if (!isFinite())
    throw FrameworkError("property '" + name_ + "': value " + formatValue() +
                         " is not finite");
  const double v = numericValue();
  if (!std::isnan(v) && (v < range_.min || v > range_.max))
    throw FrameworkError("property '" + name_ + "': value " + formatValue() +
                         " is outside the allowed range " + formatRange());
}

void parsePropertyText(const std::string& text, double& value) {
  const std::string token = trimmed(text);
  if (!parseDoubleToken(token, value))
    throw FrameworkError("expected a number, got '" + token + "'");
}

void parsePropertyText(const std::string& text, int& value) {
  const std::string token = trimmed(text);
  char* end = nullptr;
  errno = 0;
  const long parsed = token.empty() ? 0 : std::strtol(token.c_str(), &end, 10);
  if (token.empty() || end != token.c_str() + token.size() || errno == ERANGE ||
      parsed < std::numeric_limits<int>::min() || parsed > std::numeric_limits<int>::max())
    throw FrameworkError("expected an integer, got '" + token + "'");
  value = static_cast<int>(parsed);
}

void parsePropertyText(const std::string& text, bool& value) {
  const std::string token = trimmed(text);
  if (token == "true" || token == "1") {
    value = true;
  } else if (token == "false" || token == "0") {
    value = false;
  } else {
    throw FrameworkError("expected true or false, got '" + token + "'");
  }
}

void parsePropertyText(const std::string& text, std::string& value) { value = trimmed(text); }

void parsePropertyText(const std::string& text, Eigen::Vector3d& value) {
  std::istringstream in(text);
  std::string token;
  int count = 0;
  Eigen::Vector3d parsed;
  while (in >> token) {
    double component = 0.0;
    if (count >= 3 || !parseDoubleToken(token, component))
      throw FrameworkError("expected three numbers separated by spaces, got '" + trimmed(text) +
                           "'");
    parsed[count++] = component;
  }
  if (count != 3)
    throw FrameworkError("expected three numbers separated by spaces, got '" + trimmed(text) +
                         "'");
  value = parsed;
}

std::string formatPropertyValue(double value) { return formatDouble(value); }
std::string formatPropertyValue(int value) { return std::to_string(value); }
std::string formatPropertyValue(bool value) { return value ? "true" : "false"; }
std::string formatPropertyValue(const std::string& value) { return value; }
std::string formatPropertyValue(const Eigen::Vector3d& value) {
  return formatDouble(value.x()) + " " + formatDouble(value.y()) + " " + formatDouble(value.z());
}

}  // namespace rbfmuscle
