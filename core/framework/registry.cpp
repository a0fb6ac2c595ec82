// SPDX-License-Identifier: Apache-2.0
#include "framework/registry.h"

#include "framework/subcomponent.h"

#include <cctype>
#include <sstream>

namespace rbfmuscle {

void Registry::addType(const std::string& class_name, const std::string& description,
                       std::function<std::unique_ptr<Component>()> factory) {
  const bool valid =
      !class_name.empty() && std::isalpha(static_cast<unsigned char>(class_name[0])) &&
      class_name.find_first_not_of(
          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") == std::string::npos;
  const std::string where = current_origin_.empty() ? "" : "plugin " + current_origin_ + ": ";
  if (!valid)
    throw FrameworkError(where + "component class name '" + class_name +
                         "' is not a valid XML element name");
  if (const ComponentType* existing = findType(class_name))
    throw FrameworkError(where + "component class '" + class_name + "' is already registered" +
                         (existing->origin.empty() ? "" : " by " + existing->origin));
  if (!factory) throw FrameworkError(where + "component class '" + class_name + "' has no factory");
  types_.push_back({class_name, description, current_origin_, std::move(factory)});
}

const ComponentType* Registry::findType(const std::string& class_name) const {
  for (const auto& type : types_)
    if (type.class_name == class_name) return &type;
  return nullptr;
}

std::string Registry::listTypeNames() const {
  if (types_.empty()) return "none; load a plugin with -L or <plugin file=...>";
  std::string text;
  for (const auto& type : types_) text += (text.empty() ? "" : ", ") + type.class_name;
  return text;
}

std::unique_ptr<Component> Registry::create(const std::string& class_name) const {
  const ComponentType* type = findType(class_name);
  if (type == nullptr)
    throw FrameworkError("unknown component class '" + class_name + "' (registered: " +
                         listTypeNames() + ")");
  std::unique_ptr<Component> component = type->factory();
  if (!component)
    throw FrameworkError("component class '" + class_name + "': factory returned nothing");
  component->setClassName(class_name);
  return component;
}

namespace {

/// One line per property: name (type, default or required, range): description.
void describeProperties(const Component& component, const std::string& prefix, std::ostringstream& out) {
  for (const AbstractProperty* p : component.getProperties()) {
    out << "    " << prefix << p->getName() << " (" << p->getTypeName() << ", ";
    if (p->isRequired()) {
      out << "required";
    } else {
      out << "default " << (p->formatDefault().empty() ? "\"\"" : p->formatDefault());
    }
    if (!p->formatRange().empty()) out << ", range " << p->formatRange();
    out << "): " << p->getDescription() << '\n';
  }
}

}  // namespace

std::string Registry::describeType(const ComponentType& type) const {
  const std::unique_ptr<Component> component = create(type.class_name);
  std::ostringstream out;
  out << type.class_name << "  -  " << type.description << '\n';
  if (!type.origin.empty()) out << "  from " << type.origin << '\n';
  out << "  properties:" << (component->getProperties().empty() ? " none" : "") << '\n';
  describeProperties(*component, "", out);
  for (const Component* sub : component->getSubcomponents()) {
    out << "  <" << sub->getName() << ">: " << static_cast<const Subcomponent*>(sub)->getDescription() << '\n';
    describeProperties(*sub, sub->getName() + "/", out);
  }
  out << "  sockets:" << (component->getSockets().empty() ? " none" : "") << '\n';
  for (const AbstractSocket* s : component->getSockets())
    out << "    socket_" << s->getName() << " (" << s->getKind() << "): " << s->getDescription()
        << '\n';
  out << "  outputs:" << (component->getOutputs().empty() ? " none" : "") << '\n';
  for (const AbstractOutput* o : component->getOutputs())
    out << "    " << o->getName() << " (" << o->getTypeName() << ", " << o->getUnit()
        << "): " << o->getDescription() << '\n';
  return out.str();
}

}  // namespace rbfmuscle
