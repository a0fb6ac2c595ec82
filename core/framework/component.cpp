// SPDX-License-Identifier: Apache-2.0
#include "framework/component.h"

#include "framework/frame_state.h"

#include <filesystem>

namespace rbfmuscle {
namespace {

template <class T>
T* findByName(const std::vector<T*>& items, const std::string& name) {
  for (T* item : items)
    if (item->getName() == name) return item;
  return nullptr;
}

}  // namespace

std::string InitContext::resolvePath(const std::string& path) const {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  const std::filesystem::path inside = p.lexically_normal();
  if (!inside.empty() && *inside.begin() == "..")
    throw FrameworkError("path '" + path + "' leaves the model directory " + model_directory_ +
                         " (a relative path in a model file must stay inside its directory; write an absolute "
                         "path to use a file elsewhere)");
  return (std::filesystem::path(model_directory_) / inside).lexically_normal().string();
}

AbstractProperty* Component::findProperty(const std::string& name) const {
  return findByName(properties_, name);
}
AbstractSocket* Component::findSocket(const std::string& name) const {
  return findByName(sockets_, name);
}
AbstractOutput* Component::findOutput(const std::string& name) const {
  return findByName(outputs_, name);
}
Component* Component::findSubcomponent(const std::string& name) const {
  return findByName(subcomponents_, name);
}

void Component::finalizeProperties() {
  try {
    for (const AbstractProperty* property : properties_) property->validate();
  } catch (const FrameworkError& error) {
    throwAt(location_, error.what());
  }
  for (Component* sub : subcomponents_) sub->finalizeProperties();
  try {
    extendFinalizeProperties();
  } catch (const FrameworkError& error) {
    throwAt(location_, error.what());
  }
}

void Component::connectSockets(const ConnectionTargets& targets) {
  try {
    for (AbstractSocket* socket : sockets_) socket->connect(targets);
    extendConnectSockets(targets);
  } catch (const FrameworkError& error) {
    throwAt(location_, error.what());
  }
}

}  // namespace rbfmuscle
