// SPDX-License-Identifier: Apache-2.0
#include "framework/model.h"

#include <exception>

#include "framework/interrupt.h"

namespace rbfmuscle {
namespace {

std::string listNames(const std::vector<AbstractProperty*>& items) {
  std::string text;
  for (const auto* item : items) text += (text.empty() ? "" : ", ") + item->getName();
  return text.empty() ? "none" : text;
}

std::string listSocketNames(const std::vector<AbstractSocket*>& items) {
  std::string text;
  for (const auto* item : items) text += (text.empty() ? "" : ", ") + ("socket_" + item->getName());
  return text.empty() ? "none" : text;
}

std::string listSubcomponentNames(const std::vector<Component*>& items) {
  std::string text;
  for (const auto* item : items) text += (text.empty() ? "" : ", ") + ("<" + item->getName() + ">");
  return text.empty() ? "none" : text;
}

/// Sets the properties, socket targets and subcomponents a spec gives.
void applySpec(Component& component, const ComponentSpec& spec) {
  for (const PropertySpec& p : spec.properties) {
    AbstractProperty* property = component.findProperty(p.name);
    if (const Component* sub = property ? nullptr : component.findSubcomponent(p.name)) {
      if (p.text.empty()) continue;  // <fibres/>: the subcomponent's defaults
      throwAt(p.location, "'" + p.name + "' is a subcomponent: give its properties inside, as <" + p.name +
                              "><PROPERTY>value</PROPERTY></" + p.name + "> (its properties: " +
                              listNames(sub->getProperties()) + ")");
    }
    if (property == nullptr)
      throwAt(p.location, "unknown property '" + p.name + "' (" + spec.class_name +
                              " has properties: " + listNames(component.getProperties()) +
                              "; sockets: " + listSocketNames(component.getSockets()) +
                              (component.getSubcomponents().empty()
                                   ? std::string()
                                   : "; subcomponents: " + listSubcomponentNames(component.getSubcomponents())) +
                              ")");
    try {
      property->read(p.text);
    } catch (const FrameworkError& error) {
      throwAt(p.location, std::string(property->getTypeName()) + " property: " + error.what());
    }
  }
  for (const SocketSpec& s : spec.sockets) {
    AbstractSocket* socket = component.findSocket(s.name);
    if (socket == nullptr)
      throwAt(s.location, "unknown socket 'socket_" + s.name + "' (" + spec.class_name +
                              " has sockets: " + listSocketNames(component.getSockets()) + ")");
    socket->setTargetName(s.target);
  }
  for (Component* sub : component.getSubcomponents()) sub->setSourceLocation(spec.location);
  for (const ComponentSpec& s : spec.subcomponents) {
    Component* sub = component.findSubcomponent(s.name);
    if (sub == nullptr)
      throwAt(s.location, "unknown subcomponent <" + s.name + "> (" + spec.class_name +
                              " has subcomponents: " + listSubcomponentNames(component.getSubcomponents()) +
                              "; properties: " + listNames(component.getProperties()) + ")");
    sub->setSourceLocation(s.location);
    applySpec(*sub, s);
  }
}

std::unique_ptr<Component> createComponent(const ComponentSpec& spec, const Registry& registry) {
  std::unique_ptr<Component> component;
  try {
    component = registry.create(spec.class_name);
  } catch (const FrameworkError& error) {
    throwAt(spec.location, error.what());
  }
  component->setName(spec.name);
  component->setSourceLocation(spec.location);
  applySpec(*component, spec);
  component->finalizeProperties();
  return component;
}

}  // namespace

std::vector<std::unique_ptr<Component>> createComponents(const ModelDocument& document,
                                                         const Registry& registry) {
  std::vector<std::unique_ptr<Component>> components;
  for (const ComponentSpec& spec : document.components)
    components.push_back(createComponent(spec, registry));
  return components;
}

Model::Model(ModelDocument document, Skeleton skeleton, Motion motion,
             std::vector<std::unique_ptr<Component>> components)
    : document_(std::move(document)), skeleton_(std::move(skeleton)), motion_(std::move(motion)),
      components_(std::move(components)) {}

Model Model::build(ModelDocument document, const Registry& registry) {
  std::vector<std::unique_ptr<Component>> components = createComponents(document, registry);
  auto load_skeleton = [&]() -> Skeleton {
    try {
      Skeleton s = Skeleton::fromFile(document.skeleton.path);  // .urdf or .osim
      if (document.skeleton_rest_pose == RestPose::kBodiesAtGround)
        s.setRestCoordinateValues(s.solveBodiesAtGround());
      return s;
    } catch (const std::exception& error) {
      throwAt(document.skeleton.location, error.what());
    }
  };
  Skeleton skeleton = load_skeleton();
  Motion motion;
  try {
    motion = Motion::fromFile(document.motion.path, skeleton);
  } catch (const std::exception& error) {
    throwAt(document.motion.location, error.what());
  }
  std::vector<Component*> pointers;
  for (const auto& component : components) pointers.push_back(component.get());
  const ConnectionTargets targets(skeleton.getBodyNames(), pointers);
  for (const auto& component : components) component->connectSockets(targets);
  return Model(std::move(document), std::move(skeleton), std::move(motion), std::move(components));
}

void Model::initializeComponents(const std::string& output_directory, const InitProgressFn& progress) {
  // Components take the rest pose (where the meshes were segmented: all coordinates 0 for
  // the URDF scenes; see ModelDocument's rest_pose) as their reference: the skeleton is
  // there while they initialize.
  skeleton_.setCoordinateValues(skeleton_.getRestCoordinateValues());
  const InitContext context(document_.directory, output_directory, skeleton_);
  for (std::size_t c = 0; c < components_.size(); ++c) {
    const auto& component = components_[c];
    throwIfInterrupted();
    if (progress) progress(*component, static_cast<int>(c), static_cast<int>(components_.size()), false);
    try {
      component->initialize(context);
      if (progress) progress(*component, static_cast<int>(c), static_cast<int>(components_.size()), true);
    } catch (const Interrupted&) {
      throw;
    } catch (const std::exception& error) {
      throwAt(component->getSourceLocation(), std::string("initialize: ") + error.what());
    }
  }
}

}  // namespace rbfmuscle
