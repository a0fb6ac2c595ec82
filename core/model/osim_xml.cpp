// SPDX-License-Identifier: Apache-2.0
#include "model/osim_xml.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "io/file_checks.h"
#include "io/text.h"
#include "model/model_error.h"
#include "model/osim_description.h"

namespace rbfmuscle::detail {

using io::splitWords;
using io::trimWhitespace;
using tinyxml2::XMLElement;

std::string describeElement(const XMLElement& e) {
  std::string text = std::string("<") + e.Name();
  if (const char* name = e.Attribute("name")) text += std::string(" name=\"") + name + "\"";
  return text + ">";
}

std::string toLower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string lastPathComponent(const std::string& path) {
  std::string p = trimWhitespace(path);
  while (p.size() > 1 && p.back() == '/') p.pop_back();
  const auto slash = p.rfind('/');
  return slash == std::string::npos ? p : p.substr(slash + 1);
}

namespace {

/// Refuses a model of more than kMaxOsimFileBytes, checked before the file is read and again
/// for text given from memory.
void checkOsimSize(const std::string& path, std::uintmax_t bytes) {
  if (bytes > kMaxOsimFileBytes)
    throw ModelError("OpenSim model " + path + ": " + std::to_string(bytes) + " bytes, more than the " +
                     std::to_string(kMaxOsimFileBytes) + " a model file may have");
}

std::string readOsimFile(const std::string& path) {
  const std::string problem = io::findInputFileProblem(path, "an OpenSim model (.osim)");
  if (!problem.empty()) throw ModelError("OpenSim model " + path + ": " + problem);
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (!ec) checkOsimSize(path, bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError("OpenSim model " + path + ": cannot open it (unreadable)");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

OsimXml::OsimXml(std::string path) : OsimXml(path, readOsimFile(path)) {}

OsimXml::OsimXml(std::string path, const std::string& xml_text) : path_(std::move(path)) {
  checkOsimSize(path_, xml_text.size());
  if (document_.Parse(xml_text.data(), xml_text.size()) != tinyxml2::XML_SUCCESS)
    throw ModelError("OpenSim model " + path_ + ", line " + std::to_string(document_.ErrorLineNum()) +
                     ": not well-formed XML (" + document_.ErrorName() + ")");
  const XMLElement* root = document_.RootElement();
  if (root && std::strcmp(root->Name(), "OpenSimDocument") == 0) model_ = root->FirstChildElement("Model");
  else if (root && std::strcmp(root->Name(), "Model") == 0) model_ = root;
  if (!model_) fail(root, "expected <OpenSimDocument> holding a <Model>");
  const std::string units = toLower(text(*model_, "length_units"));
  if (units.empty() || units == "meters" || units == "meter" || units == "m" || units == "metres")
    to_mm_ = 1000.0;
  else if (units == "millimeters" || units == "millimetres" || units == "mm")
    to_mm_ = 1.0;
  else
    fail(model_->FirstChildElement("length_units"),
         "length units '" + units + "' are not supported (expected meters or millimeters)");
}

void OsimXml::fail(const XMLElement* e, const std::string& what) const {
  std::string m = "OpenSim model " + path_;
  if (e) m += ", line " + std::to_string(e->GetLineNum()) + ": " + describeElement(*e);
  throw ModelError(m + ": " + what);
}

std::vector<double> OsimXml::numbers(const XMLElement& e, const char* name, std::size_t count,
                                     const std::vector<double>& fallback) const {
  const XMLElement* c = e.FirstChildElement(name);
  if (!c) {
    if (fallback.size() != count) fail(&e, std::string("missing <") + name + ">");
    return fallback;
  }
  std::vector<double> out;
  for (const std::string& w : splitWords(c->GetText() ? c->GetText() : "")) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(w.c_str(), &end);
    if (*end != '\0' || end == w.c_str() || errno == ERANGE || !std::isfinite(v))
      fail(c, "'" + w + "' is not a finite number");
    out.push_back(v);
  }
  if (out.size() != count)
    fail(c, "holds " + std::to_string(out.size()) + " numbers, expected " + std::to_string(count));
  return out;
}

Eigen::Vector3d OsimXml::vec3(const XMLElement& e, const char* name, const Eigen::Vector3d& fallback) const {
  const auto v = numbers(e, name, 3, {fallback.x(), fallback.y(), fallback.z()});
  return {v[0], v[1], v[2]};
}

double OsimXml::number(const XMLElement& e, const char* name, double fallback) const {
  return numbers(e, name, 1, {fallback})[0];
}

std::string OsimXml::text(const XMLElement& e, const char* name) const {
  const XMLElement* c = e.FirstChildElement(name);
  return c && c->GetText() ? trimWhitespace(c->GetText()) : "";
}

bool OsimXml::flag(const XMLElement& e, const char* name, bool fallback) const {
  const std::string t = toLower(text(e, name));
  if (t.empty()) return fallback;
  if (t == "true" || t == "1") return true;
  if (t == "false" || t == "0") return false;
  fail(e.FirstChildElement(name), "'" + t + "' is not true or false");
}

}  // namespace rbfmuscle::detail
