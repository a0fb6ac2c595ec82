// SPDX-License-Identifier: Apache-2.0
// The attachment area property text: a file reference or inline points (grammar
// in attachment_areas.h).
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "io/text.h"
#include "model/attachment_areas.h"

namespace rbfmuscle {
namespace {

using io::splitTrimmed;
using io::trimWhitespace;

/// Throws quoting the spec (cut to 80 characters).
[[noreturn]] void fail(const std::string& spec, const std::string& what) {
  const std::string shown = spec.size() > 80 ? spec.substr(0, 77) + "..." : spec;
  throw ModelError("attachment area spec \"" + shown + "\": " + what);
}

/// "FILE: NAME, NAME, ..." read from FILE (relative to `base_directory`).
std::vector<AttachmentArea> readFileReference(const std::string& spec, std::size_t colon,
                                              const std::string& base_directory) {
  const std::string file = trimWhitespace(spec.substr(0, colon));
  if (file.empty()) fail(spec, "no file before ':'; expected \"FILE: NAME, NAME, ...\"");
  const std::string list = trimWhitespace(spec.substr(colon + 1));
  if (list.empty()) fail(spec, "no cloud names after ':'; expected \"FILE: NAME, NAME, ...\"");
  const std::vector<std::string> names = splitTrimmed(list, ',');
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i].empty())
      fail(spec, "cloud name " + std::to_string(i + 1) + " of " + std::to_string(names.size()) +
                     " is empty (a stray ','?)");
  std::filesystem::path path(file);
  if (path.is_relative() && !base_directory.empty())
    path = std::filesystem::path(base_directory) / path;
  return readAttachmentAreas(path.string(), names);
}

/// "x y z; x y z; ..." as one area named "inline".
AttachmentArea readInlinePoints(const std::string& spec) {
  std::vector<std::string> points = splitTrimmed(spec, ';');
  if (points.size() > 1 && points.back().empty()) points.pop_back();  // trailing ';'
  const std::size_t n = points.size();
  AttachmentArea area{"inline", Eigen::Matrix3Xd(3, static_cast<Eigen::Index>(n))};
  for (std::size_t i = 0; i < n; ++i) {
    const std::string at = "inline point " + std::to_string(i + 1) + " of " + std::to_string(n);
    std::istringstream in(points[i]);
    std::vector<std::string> tokens;
    for (std::string token; in >> token;) tokens.push_back(token);
    if (tokens.empty()) fail(spec, at + " is empty (a stray ';'?)");
    std::vector<double> values;
    for (const std::string& token : tokens) {
      char* end = nullptr;
      values.push_back(std::strtod(token.c_str(), &end));
      if (end == token.c_str() || *end != '\0')
        fail(spec, at + ": \"" + token + "\" is not a number" +
                       " (a file reference is written \"FILE: NAME, NAME, ...\")");
    }
    if (tokens.size() != 3)
      fail(spec, at + " has " + std::to_string(tokens.size()) + " values (\"" + points[i] +
                     "\"); expected 3 numbers \"x y z\" (mm)");
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string axis(1, "xyz"[k]);
      const double value = values[k];
      if (!std::isfinite(value))
        fail(spec, at + ": coordinate " + axis + " \"" + tokens[k] +
                       "\" is not finite; expected a finite number (mm)");
      if (std::abs(value) > kMaxAttachmentCoordinateMm) {
        std::ostringstream m;
        m << at << ": coordinate " << axis << " = " << value
          << " mm is implausible (magnitude above " << kMaxAttachmentCoordinateMm << " mm)";
        fail(spec, m.str());
      }
      area.points_mm(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = value;
    }
  }
  return area;
}

}  // namespace

std::vector<AttachmentArea> parseAttachmentAreaSpec(const std::string& spec,
                                                    const std::string& base_directory) {
  const std::string text = trimWhitespace(spec);
  if (text.empty())
    throw ModelError(
        "attachment area spec is empty; expected \"FILE: NAME, NAME, ...\" or inline points "
        "\"x y z; x y z; ...\" (mm)");
  const std::size_t colon = text.find(':');
  if (colon != std::string::npos) return readFileReference(text, colon, base_directory);
  return {readInlinePoints(text)};
}

}  // namespace rbfmuscle
