// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to core/model: reading an OpenSim model file's XML (tinyxml2, for line numbers in
/// every error), shared by the skeleton reader (osim_description.h, its joints in osim_joints.h)
/// and the muscle path reader (osim_muscle_path.h). Lengths are converted from the model's
/// `<length_units>` to mm here.
#include <tinyxml2.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace rbfmuscle::detail {

/// `<Name name="value">` or `<Name>`.
std::string describeElement(const tinyxml2::XMLElement& e);
std::string toLower(std::string s);
/// Last component of an OpenSim component path ("/bodyset/pelvis" → "pelvis").
std::string lastPathComponent(const std::string& path);

/// An OpenSim model file open for reading: its `<Model>` element, its length unit, and typed
/// reads of child elements that throw ModelError "OpenSim model PATH, line N: <Element>: …".
class OsimXml {
 public:
  /// Loads the file. @throws ModelError naming the file when it is missing, not a regular
  ///   file, larger than kMaxOsimFileBytes, not well-formed XML (with the line), has no
  ///   `<Model>`, or unsupported length units.
  explicit OsimXml(std::string path);
  /// Parses `xml_text`, the text of the file `path` (which names it in errors).
  /// @throws ModelError as the file constructor.
  OsimXml(std::string path, const std::string& xml_text);

  const std::string& getPath() const { return path_; }
  const tinyxml2::XMLElement& getModel() const { return *model_; }
  /// Multiply model lengths by this to get mm.
  double getLengthToMm() const { return to_mm_; }

  [[noreturn]] void fail(const tinyxml2::XMLElement* e, const std::string& what) const;
  /// The numbers of child `name` of `e`; `fallback` when there is no such child.
  std::vector<double> numbers(const tinyxml2::XMLElement& e, const char* name, std::size_t count,
                              const std::vector<double>& fallback) const;
  Eigen::Vector3d vec3(const tinyxml2::XMLElement& e, const char* name, const Eigen::Vector3d& fallback) const;
  double number(const tinyxml2::XMLElement& e, const char* name, double fallback) const;
  /// The trimmed text of child `name`, or "" without one.
  std::string text(const tinyxml2::XMLElement& e, const char* name) const;
  bool flag(const tinyxml2::XMLElement& e, const char* name, bool fallback) const;

 private:
  std::string path_;
  tinyxml2::XMLDocument document_;
  const tinyxml2::XMLElement* model_ = nullptr;
  double to_mm_ = 1000.0;
};

}  // namespace rbfmuscle::detail
