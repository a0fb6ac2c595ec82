// SPDX-License-Identifier: Apache-2.0
#include "framework/socket.h"

#include "framework/component.h"
#include "framework/framework_error.h"

#include <sstream>

namespace rbfmuscle {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
  return text.empty() ? "none" : text;
}

}  // namespace

ConnectionTargets::ConnectionTargets(std::vector<std::string> body_names,
                                     std::vector<Component*> components)
    : body_names_(std::move(body_names)), components_(std::move(components)) {}

int ConnectionTargets::findBody(const std::string& name) const {
  for (std::size_t i = 0; i < body_names_.size(); ++i)
    if (body_names_[i] == name) return static_cast<int>(i);
  return -1;
}

Component* ConnectionTargets::findComponent(const std::string& name) const {
  for (Component* component : components_)
    if (component->getName() == name) return component;
  return nullptr;
}

std::string ConnectionTargets::listBodies() const { return joined(body_names_); }

std::string ConnectionTargets::listComponents() const {
  std::vector<std::string> names;
  for (const Component* component : components_) names.push_back(component->getName());
  return joined(names);
}

AbstractSocket::AbstractSocket(Component* owner, std::string name, std::string description)
    : name_(std::move(name)), description_(std::move(description)) {
  owner->sockets_.push_back(this);
}

void AbstractSocket::connect(const ConnectionTargets& targets) {
  connected_ = false;
  try {
    if (target_.empty())
      throw FrameworkError("is not connected: expected a <socket_" + name_ + "> element naming a " +
                           getKind());
    resolve(targets);
  } catch (const FrameworkError& error) {
    throw FrameworkError("socket '" + name_ + "' " + error.what());
  }
  connected_ = true;
}

void BodySocket::resolve(const ConnectionTargets& targets) {
  body_index_ = targets.findBody(getTargetName());
  if (body_index_ < 0)
    throw FrameworkError("names unknown body '" + getTargetName() +
                         "' (skeleton bodies: " + targets.listBodies() + ")");
}

void BodyListSocket::resolve(const ConnectionTargets& targets) {
  body_indices_.clear();
  std::istringstream in(getTargetName());
  std::string body;
  while (in >> body) {
    const int index = targets.findBody(body);
    if (index < 0)
      throw FrameworkError("names unknown body '" + body + "' (skeleton bodies: " +
                           targets.listBodies() + ")");
    body_indices_.push_back(index);
  }
  if (body_indices_.empty())
    throw FrameworkError("is empty: expected body names separated by spaces");
}

void throwBadComponentTarget(const ConnectionTargets& targets, const std::string& target,
                             const std::string& type_name, bool exists) {
  if (exists)
    throw FrameworkError("names component '" + target + "', which is not a " + type_name);
  throw FrameworkError("names unknown component '" + target + "' (components: " +
                       targets.listComponents() + ")");
}

}  // namespace rbfmuscle
