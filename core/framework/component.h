// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Component: the unit a model is built from (OpenSim-style). A component
/// class declares its properties, sockets and outputs as members at the top
/// of the class; the framework reads them from XML and drives the lifecycle:
///
///   construct (Registry factory) → properties read from XML →
///   finalizeProperties() (presence, range, extendFinalizeProperties()) →
///   connectSockets() (names → bodies/components, extendConnectSockets()) →
///   initialize(InitContext) (heavy setup: load meshes, fit, build BVHs) →
///   update(FrameState) each frame (fills a result struct; no allocation) →
///   outputs read the result struct; appendFrameGeometry() for --frames-mesh;
///   the run loop checks the invariants the component declared on its outputs.
///
/// Components are neither copyable nor movable: members register themselves
/// with `this`.
#include "framework/frame_geometry.h"
#include "framework/frame_state.h"
#include "framework/framework_error.h"
#include "framework/invariant.h"
#include "framework/output.h"
#include "framework/property.h"
#include "framework/socket.h"

#include <string>
#include <vector>

namespace rbfmuscle {

class Component {
 public:
  Component() = default;
  Component(const Component&) = delete;
  Component& operator=(const Component&) = delete;
  virtual ~Component() = default;

  /// Instance name (XML `name` attribute); unique in a model, no '.'.
  const std::string& getName() const { return name_; }
  void setName(std::string name) { name_ = std::move(name); }
  /// Registered class name (set by Registry::create).
  const std::string& getClassName() const { return class_name_; }
  void setClassName(std::string class_name) { class_name_ = std::move(class_name); }
  /// Where the component was declared, for error messages.
  const SourceLocation& getSourceLocation() const { return location_; }
  void setSourceLocation(SourceLocation location) { location_ = std::move(location); }

  const std::vector<AbstractProperty*>& getProperties() const { return properties_; }
  const std::vector<AbstractSocket*>& getSockets() const { return sockets_; }
  const std::vector<AbstractOutput*>& getOutputs() const { return outputs_; }
  /// Promises about this component's outputs that the run loop checks after every frame.
  const std::vector<Invariant>& getInvariants() const { return invariants_; }
  /// Components nested in this one, in declaration order (subcomponent.h).
  const std::vector<Component*>& getSubcomponents() const { return subcomponents_; }
  /// nullptr when there is none of that name.
  AbstractProperty* findProperty(const std::string& name) const;
  AbstractSocket* findSocket(const std::string& name) const;
  AbstractOutput* findOutput(const std::string& name) const;
  Component* findSubcomponent(const std::string& name) const;

  /// Checks every property (required present, finite, in range), then every
  /// subcomponent's, then extendFinalizeProperties(). @throws FrameworkError
  /// prefixed with the source location.
  void finalizeProperties();
  /// Connects every socket, then extendConnectSockets().
  /// @throws FrameworkError prefixed with the source location.
  void connectSockets(const ConnectionTargets& targets);

  /// Heavy one-time setup. Errors: throw FrameworkError (or ModelError); the
  /// framework prefixes the source location.
  virtual void initialize(const InitContext& context) { (void)context; }
  /// Computes this frame's result from the realized skeleton.
  virtual void update(const FrameState& state) = 0;
  /// Appends this frame's geometry (ground, mm) for --frames-mesh; default none.
  virtual void appendFrameGeometry(std::vector<FrameGeometry>& geometry) const { (void)geometry; }

 protected:
  /// Cross-property checks; throw FrameworkError("property 'x': ...").
  virtual void extendFinalizeProperties() {}
  /// Checks after all sockets are connected (e.g. two sockets differ).
  virtual void extendConnectSockets(const ConnectionTargets& targets) { (void)targets; }
  /// Declares a promise about one of this component's outputs (invariant.h), from the
  /// constructor or initialize(); the run loop refuses one that names no output.
  void declareInvariant(Invariant invariant) { invariants_.push_back(std::move(invariant)); }

 private:
  friend class AbstractProperty;
  friend class AbstractSocket;
  friend class AbstractOutput;
  friend class Subcomponent;

  std::string name_;
  std::string class_name_;
  SourceLocation location_;
  std::vector<AbstractProperty*> properties_;
  std::vector<AbstractSocket*> sockets_;
  std::vector<AbstractOutput*> outputs_;
  std::vector<Invariant> invariants_;
  std::vector<Component*> subcomponents_;
};

}  // namespace rbfmuscle
