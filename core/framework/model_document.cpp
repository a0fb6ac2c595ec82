// SPDX-License-Identifier: Apache-2.0
#include "framework/model_document.h"

#include <tinyxml2.h>

#include "io/file_checks.h"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;
using tinyxml2::XMLAttribute;
using tinyxml2::XMLElement;

/// `<Name name="value">` or `<Name>`.
std::string describeElement(const XMLElement& element) {
  std::string text = std::string("<") + element.Name();
  if (const char* name = element.Attribute("name")) text += std::string(" name=\"") + name + "\"";
  return text + ">";
}

SourceLocation locate(const std::string& file, const XMLElement& element,
                      const std::string& context = "") {
  std::string text = describeElement(element);
  if (!context.empty()) text += " in " + context;
  return {file, element.GetLineNum(), text};
}

std::string elementText(const XMLElement& element) {
  const char* text = element.GetText();
  return text ? text : "";
}

/// Rejects attributes other than `allowed`.
void checkAttributes(const std::string& file, const XMLElement& element,
                     const std::set<std::string>& allowed) {
  for (const XMLAttribute* a = element.FirstAttribute(); a != nullptr; a = a->Next()) {
    if (allowed.count(a->Name()) == 0) {
      std::string list;
      for (const auto& name : allowed) list += (list.empty() ? "" : ", ") + name;
      throwAt(locate(file, element), std::string("unknown attribute '") + a->Name() +
                                         "' (expected: " + (list.empty() ? "none" : list) + ")");
    }
  }
}

FileReference readFileReference(const ModelDocument& doc, const XMLElement& element,
                                bool resolve, const std::set<std::string>& more_attributes = {}) {
  std::set<std::string> allowed = more_attributes;
  allowed.insert("file");
  checkAttributes(doc.path, element, allowed);
  const char* file = element.Attribute("file");
  if (file == nullptr || std::string(file).empty())
    throwAt(locate(doc.path, element), "missing attribute 'file' (expected a path)");
  FileReference ref;
  ref.as_written = file;
  ref.location = locate(doc.path, element);
  const fs::path p(file);
  ref.path = (!resolve || p.is_absolute()) ? std::string(file)
                                           : (fs::path(doc.directory) / p).lexically_normal().string();
  return ref;
}

/// The properties, sockets and subcomponents of a component's element.
void readComponentContent(const ModelDocument& doc, const XMLElement& element, ComponentSpec& spec) {
  std::set<std::string> seen;
  const std::string context = describeElement(element);
  for (const XMLElement* child = element.FirstChildElement(); child != nullptr;
       child = child->NextSiblingElement()) {
    const std::string child_name = child->Name();
    const SourceLocation where = locate(doc.path, *child, context);
    if (!seen.insert(child_name).second) throwAt(where, "given twice");
    checkAttributes(doc.path, *child, {});
    const std::string prefix = "socket_";
    if (child->FirstChildElement() != nullptr) {  // a subcomponent's properties
      if (child_name.compare(0, prefix.size(), prefix) == 0)
        throwAt(where, "expected text only, found child element <" + std::string(child->FirstChildElement()->Name()) + ">");
      ComponentSpec sub;
      sub.class_name = sub.name = child_name;
      sub.location = where;
      readComponentContent(doc, *child, sub);
      spec.subcomponents.push_back(std::move(sub));
    } else if (child_name.compare(0, prefix.size(), prefix) == 0) {
      std::istringstream words(elementText(*child));
      std::string target, word;
      while (words >> word) target += (target.empty() ? "" : " ") + word;
      spec.sockets.push_back({child_name.substr(prefix.size()), target, where});
    } else {
      spec.properties.push_back({child_name, elementText(*child), where});
    }
  }
}

ComponentSpec readComponent(const ModelDocument& doc, const XMLElement& element) {
  ComponentSpec spec;
  spec.class_name = element.Name();
  spec.location = locate(doc.path, element);
  checkAttributes(doc.path, element, {"name"});
  const char* name = element.Attribute("name");
  if (name == nullptr || std::string(name).empty())
    throwAt(spec.location, "missing attribute 'name' (expected a component name)");
  spec.name = name;
  if (spec.name.find_first_of("./ \t") != std::string::npos)
    throwAt(spec.location, "component name '" + spec.name +
                               "' may not contain '.', '/' or spaces (it prefixes output columns)");
  readComponentContent(doc, element, spec);
  return spec;
}

}  // namespace

ModelDocument parseModelDocument(const std::string& xml_text, const std::string& path) {
  ModelDocument doc;
  doc.path = path;
  doc.directory = fs::absolute(fs::path(path)).parent_path().lexically_normal().string();
  doc.name = fs::path(path).stem().string();

  tinyxml2::XMLDocument xml;
  if (xml.Parse(xml_text.c_str(), xml_text.size()) != tinyxml2::XML_SUCCESS)
    throwAt({path, xml.ErrorLineNum(), ""},
            std::string("XML syntax error: ") + (xml.ErrorStr() ? xml.ErrorStr() : "unknown"));
  const XMLElement* root = xml.RootElement();
  if (root == nullptr) throwAt({path, 0, ""}, "no root element (expected <RBFMuscleModel>)");
  if (std::string(root->Name()) != "RBFMuscleModel")
    throwAt(locate(path, *root), "expected root element <RBFMuscleModel>");
  checkAttributes(path, *root, {"version", "name"});
  const char* version = root->Attribute("version");
  if (version == nullptr)
    throwAt(locate(path, *root), "missing attribute 'version' (expected version=\"" +
                                     std::to_string(kModelFileVersion) + "\")");
  if (std::string(version) != std::to_string(kModelFileVersion))
    throwAt(locate(path, *root), std::string("unsupported version '") + version +
                                     "' (this build reads version " +
                                     std::to_string(kModelFileVersion) + ")");
  doc.version = kModelFileVersion;
  if (const char* name = root->Attribute("name")) doc.name = name;

  bool have_skeleton = false, have_motion = false, have_components = false, have_reporter = false;
  auto once = [&](bool& flag, const XMLElement& element) {
    if (flag) throwAt(locate(path, element), "given twice (expected at most one)");
    flag = true;
  };
  for (const XMLElement* child = root->FirstChildElement(); child != nullptr;
       child = child->NextSiblingElement()) {
    const std::string name = child->Name();
    if (name == "skeleton") {
      once(have_skeleton, *child);
      doc.skeleton = readFileReference(doc, *child, true, {"rest_pose"});
      if (const char* rest = child->Attribute("rest_pose")) {
        const std::string value = rest;
        if (value == "default") doc.skeleton_rest_pose = RestPose::kDefault;
        else if (value == "bodies_at_ground") doc.skeleton_rest_pose = RestPose::kBodiesAtGround;
        else
          throwAt(locate(path, *child), "rest_pose '" + value + "' (expected default or bodies_at_ground)");
      }
    } else if (name == "plugin") {
      doc.plugins.push_back(readFileReference(doc, *child, false));
    } else if (name == "motion") {
      once(have_motion, *child);
      doc.motion = readFileReference(doc, *child, true);
    } else if (name == "components") {
      once(have_components, *child);
      checkAttributes(path, *child, {});
      std::set<std::string> names;
      for (const XMLElement* e = child->FirstChildElement(); e != nullptr;
           e = e->NextSiblingElement()) {
        ComponentSpec spec = readComponent(doc, *e);
        if (!names.insert(spec.name).second)
          throwAt(spec.location, "duplicate component name '" + spec.name + "'");
        doc.components.push_back(std::move(spec));
      }
    } else if (name == "reporter") {
      once(have_reporter, *child);
      checkAttributes(path, *child, {"outputs"});
      doc.reporter_location = locate(path, *child);
      doc.reporter_patterns.clear();
      std::istringstream words(child->Attribute("outputs") ? child->Attribute("outputs") : "*");
      std::string word;
      while (words >> word) doc.reporter_patterns.push_back(word);
    } else {
      throwAt(locate(path, *child),
              "unknown element (expected skeleton, plugin, motion, components or reporter)");
    }
  }
  if (!have_skeleton) throwAt(locate(path, *root), "missing <skeleton file=\"...\"/>");
  if (!have_motion) throwAt(locate(path, *root), "missing <motion file=\"...\"/>");
  return doc;
}

ModelDocument readModelDocument(const std::string& path) {
  const std::string problem = io::findInputFileProblem(path, "a model XML file");
  if (!problem.empty()) throw FrameworkError("model file " + path + ": " + problem);
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (!ec && bytes > kMaxModelFileBytes)
    throw FrameworkError("model file " + path + ": " + std::to_string(bytes) + " bytes, more than the " +
                         std::to_string(kMaxModelFileBytes) + " a model file may have");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FrameworkError("model file " + path + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return parseModelDocument(text.str(), path);
}

}  // namespace rbfmuscle
