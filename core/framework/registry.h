// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Registry of component classes: class name → factory and description.
/// The host owns one; plugins fill it from their entry point
///
///     extern "C" void rbfmuscle_register_types(rbfmuscle::Registry& registry) {
///       registry.addType<BodyOriginReporter>("BodyOriginReporter", "reports a body point in ground");
///     }
///
/// No globals and no static self-registration.
#include "framework/component.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rbfmuscle {

/// One registered component class.
struct ComponentType {
  std::string class_name;   ///< XML element name
  std::string description;  ///< one line for `info`
  std::string origin;       ///< plugin library that registered it ("" = host)
  std::function<std::unique_ptr<Component>()> factory;
};

class Registry {
 public:
  /// Registers `class_name` with a factory.
  /// @throws FrameworkError when the name is already registered (naming both origins)
  ///   or is not a valid XML element name.
  void addType(const std::string& class_name, const std::string& description,
               std::function<std::unique_ptr<Component>()> factory);
  /// Registers T (default-constructible Component subclass).
  template <class T>
  void addType(const std::string& class_name, const std::string& description) {
    addType(class_name, description, [] { return std::unique_ptr<Component>(new T()); });
  }

  /// nullptr when not registered.
  const ComponentType* findType(const std::string& class_name) const;
  /// Registered types in registration order.
  const std::vector<ComponentType>& getTypes() const { return types_; }
  /// "A, B, C" (or "none — load a plugin with -L").
  std::string listTypeNames() const;

  /// A new default-constructed component with its class name set.
  /// @throws FrameworkError "unknown component class 'X' (registered: ...)".
  std::unique_ptr<Component> create(const std::string& class_name) const;

  /// Multi-line description of one type: properties (type, default, range,
  /// description), sockets (kind) and outputs (type, unit), as `rbfmuscle info` prints it.
  std::string describeType(const ComponentType& type) const;

  /// Origin recorded for types added from now on (set by the plugin loader).
  void setCurrentOrigin(std::string origin) { current_origin_ = std::move(origin); }

 private:
  std::vector<ComponentType> types_;
  std::string current_origin_;
};

}  // namespace rbfmuscle
