#include "host/model_overrides.h"

#include "host_commands.h"

#include <algorithm>
#include <filesystem>

namespace rbfmuscle {

void applyPropertyOverride(ModelDocument& document, const std::string& assignment) {
  const std::size_t dot = assignment.find('.');
  const std::size_t equals = assignment.find('=');
  if (dot == std::string::npos || equals == std::string::npos || dot == 0 || dot + 1 >= equals)
    throw UsageError("--set expects COMPONENT.PROPERTY=VALUE, got '" + assignment + "'");
  const std::string component = assignment.substr(0, dot);
  const std::string property = assignment.substr(dot + 1, equals - dot - 1);
  const std::string value = assignment.substr(equals + 1);
  const SourceLocation where{"command line", 0, "--set " + assignment};

  auto spec = std::find_if(document.components.begin(), document.components.end(),
                           [&](const ComponentSpec& c) { return c.name == component; });
  if (spec == document.components.end()) {
    std::string names;
    for (const ComponentSpec& c : document.components) names += (names.empty() ? "" : ", ") + c.name;
    throwAt(where, "no component '" + component + "' in " + document.path +
                       " (components: " + (names.empty() ? "none" : names) + ")");
  }
  if (property.compare(0, 7, "socket_") == 0)
    throwAt(where, "'" + property + "' is a socket; --set changes properties only");
  for (PropertySpec& p : spec->properties) {
    if (p.name == property) {
      p.text = value;
      p.location = where;
      return;
    }
  }
  spec->properties.push_back({property, value, where});
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
