// SPDX-License-Identifier: Apache-2.0
#include "host/model_overrides.h"

#include "host/usage_error.h"

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <vector>

namespace rbfmuscle {

void applyPropertyOverride(ModelDocument& document, const std::string& assignment) {
  const std::size_t equals = assignment.find('=');
  const std::size_t dot = assignment.rfind('.', equals);
  if (dot == std::string::npos || equals == std::string::npos || dot == 0 || dot + 1 >= equals)
    throw UsageError("--set expects COMPONENT.PROPERTY=VALUE (or COMPONENT/SUBCOMPONENT.PROPERTY=VALUE), got '" +
                     assignment + "'");
  // Component, then subcomponents, then the property: "C/SUB.P" and "C.SUB/P" (as
  // `rbfmuscle info` lists a subcomponent's property) name the same one.
  std::vector<std::string> path;
  std::stringstream parts(assignment.substr(0, dot) + '/' + assignment.substr(dot + 1, equals - dot - 1));
  for (std::string part; std::getline(parts, part, '/');) path.push_back(part);
  const std::string property = path.back();
  path.pop_back();
  if (property.empty()) throw UsageError("--set: an empty property name in '" + assignment + "'");
  const std::string value = assignment.substr(equals + 1);
  const SourceLocation where{"command line", 0, "--set " + assignment};

  auto spec = std::find_if(document.components.begin(), document.components.end(),
                           [&](const ComponentSpec& c) { return c.name == path[0]; });
  if (spec == document.components.end()) {
    std::string names;
    for (const ComponentSpec& c : document.components) names += (names.empty() ? "" : ", ") + c.name;
    throwAt(where, "no component '" + path[0] + "' in " + document.path +
                       " (components: " + (names.empty() ? "none" : names) + ")");
  }
  ComponentSpec* target = &*spec;
  for (size_t i = 1; i < path.size(); ++i) {  // a subcomponent missing from the file is added; the model checks its name
    if (path[i].empty()) throw UsageError("--set: an empty subcomponent name in '" + assignment + "'");
    auto sub = std::find_if(target->subcomponents.begin(), target->subcomponents.end(),
                            [&](const ComponentSpec& c) { return c.name == path[i]; });
    if (sub == target->subcomponents.end()) {
      target->subcomponents.push_back(ComponentSpec{path[i], path[i], where, {}, {}, {}});
      sub = target->subcomponents.end() - 1;
    }
    target = &*sub;
  }
  if (property.compare(0, 7, "socket_") == 0)
    throwAt(where, "'" + property + "' is a socket; --set changes properties only");
  for (PropertySpec& p : target->properties) {
    if (p.name == property) {
      p.text = value;
      p.location = where;
      return;
    }
  }
  target->properties.push_back({property, value, where});
}

void overrideMotion(ModelDocument& document, const std::string& path) {
  if (path.empty()) throw UsageError("--motion needs a file name");
  document.motion.as_written = path;
  document.motion.path = std::filesystem::absolute(path).lexically_normal().string();
  document.motion.location = {"command line", 0, "--motion " + path};
}

void overrideReporter(ModelDocument& document, const std::vector<std::string>& patterns) {
  std::string all;
  for (const std::string& pattern : patterns) {
    if (pattern.empty()) throw UsageError("--report needs a pattern COMPONENT.OUTPUT");
    all += (all.empty() ? "" : " ") + pattern;
  }
  document.reporter_patterns = patterns;
  document.reporter_location = {"command line", 0, "--report " + all};
}

}  // namespace rbfmuscle
