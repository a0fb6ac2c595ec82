// SPDX-License-Identifier: Apache-2.0
#include "model/osim_muscle_path.h"

#include <cstring>
#include <filesystem>
#include <sstream>

#include "io/text.h"
#include "model/osim_xml.h"
#include "model/skeleton.h"

namespace rbfmuscle {
namespace {

using detail::OsimXml;
using tinyxml2::XMLElement;

const XMLElement* child(const XMLElement& e, const char* name) { return e.FirstChildElement(name); }

/// The elements of the model's ForceSet that have a GeometryPath.
std::vector<const XMLElement*> findPathForces(const XMLElement& model) {
  std::vector<const XMLElement*> out;
  const XMLElement* set = child(model, "ForceSet");
  const XMLElement* objects = set ? child(*set, "objects") : nullptr;
  if (objects)
    for (const XMLElement* f = objects->FirstChildElement(); f; f = f->NextSiblingElement())
      if (child(*f, "GeometryPath")) out.push_back(f);
  return out;
}

/// Skeleton index of the body a path point's frame names (3.x `<body>`, 4.x socket path).
int readPointBody(const OsimXml& xml, const XMLElement& point, const Skeleton& skeleton) {
  std::string frame = xml.text(point, "body");
  if (frame.empty()) frame = detail::lastPathComponent(xml.text(point, "socket_parent_frame"));
  if (frame.empty()) xml.fail(&point, "names no body (expected <body> or <socket_parent_frame>)");
  const int body = skeleton.findBodyIndex(frame);
  if (body < 0)
    xml.fail(&point, "frame '" + frame + "' is not a body of the skeleton (a point on a PhysicalOffsetFrame is not "
                     "supported; give its location in the body's frame)");
  return body;
}

MusclePathPoint readPoint(const OsimXml& xml, const XMLElement& e, const Skeleton& skeleton) {
  MusclePathPoint p;
  p.name = e.Attribute("name") ? e.Attribute("name") : "";
  p.body = readPointBody(xml, e, skeleton);
  const std::vector<double> location = xml.numbers(e, "location", 3, {});
  p.location_B_mm = xml.getLengthToMm() * Eigen::Vector3d(location[0], location[1], location[2]);
  if (std::strcmp(e.Name(), "ConditionalPathPoint") != 0) return p;
  std::string coordinate = xml.text(e, "coordinate");
  if (coordinate.empty()) coordinate = detail::lastPathComponent(xml.text(e, "socket_coordinate"));
  p.coordinate = skeleton.findCoordinateIndex(coordinate);
  if (p.coordinate < 0) xml.fail(&e, "coordinate '" + coordinate + "' is not a coordinate of the skeleton");
  const std::vector<double> range = xml.numbers(e, "range", 2, {});
  const bool translational =
      skeleton.getCoordinates()[static_cast<size_t>(p.coordinate)].motion == CoordinateMotion::kTranslational;
  const double scale = translational ? xml.getLengthToMm() : 1.0;
  p.active_min = scale * range[0];
  p.active_max = scale * range[1];
  if (!(p.active_min <= p.active_max)) xml.fail(child(e, "range"), "minimum above maximum");
  return p;
}

bool sameFile(const std::string& a, const std::string& b) {
  std::error_code error;
  return std::filesystem::equivalent(a, b, error);
}

}  // namespace

MusclePath readOsimMusclePath(const std::string& osim_path, const std::string& muscle, const Skeleton& skeleton) {
  const OsimXml xml(osim_path);
  if (!sameFile(osim_path, skeleton.getModelPath()))
    throw ModelError("OpenSim model " + osim_path + ": muscle '" + muscle + "': its path points are given in this " +
                     "model's body frames, but the skeleton is read from " + skeleton.getModelPath() +
                     "; give this model as the scene's <skeleton>");
  const std::vector<const XMLElement*> forces = findPathForces(xml.getModel());
  const XMLElement* found = nullptr;
  for (const XMLElement* f : forces)
    if (const char* name = f->Attribute("name"); name && muscle == name) found = f;
  if (!found) {
    std::string names;
    for (const XMLElement* f : forces) names += (names.empty() ? "" : ", ") + std::string(f->Attribute("name") ? f->Attribute("name") : "?");
    throw ModelError("OpenSim model " + osim_path + ": no muscle '" + muscle + "' (a ForceSet element with a " +
                     "GeometryPath); the model has: " + (names.empty() ? "none" : names));
  }
  MusclePath path;
  path.muscle = muscle;
  const XMLElement& geometry = *child(*found, "GeometryPath");
  const XMLElement* set = child(geometry, "PathPointSet");
  const XMLElement* objects = set ? child(*set, "objects") : nullptr;
  for (const XMLElement* e = objects ? objects->FirstChildElement() : nullptr; e; e = e->NextSiblingElement()) {
    if (std::strcmp(e->Name(), "PathPoint") != 0 && std::strcmp(e->Name(), "ConditionalPathPoint") != 0)
      xml.fail(e, std::string("path points of type ") + e->Name() +
                      " are not supported (PathPoint and ConditionalPathPoint are)");
    path.points.push_back(readPoint(xml, *e, skeleton));
  }
  if (path.points.size() < 2)
    xml.fail(found, "its path has " + std::to_string(path.points.size()) + " points; expected at least 2");
  const XMLElement* wraps = child(geometry, "PathWrapSet");
  const XMLElement* wrap_objects = wraps ? child(*wraps, "objects") : nullptr;
  for (const XMLElement* w = wrap_objects ? wrap_objects->FirstChildElement() : nullptr; w; w = w->NextSiblingElement())
    path.notes.push_back("wrapping over '" + xml.text(*w, "wrap_object") + "' (line " +
                         std::to_string(w->GetLineNum()) + ") is not modelled: the path runs straight between its points");
  return path;
}

std::optional<OsimMuscleReference> parseOsimMuscleReference(const std::string& spec) {
  const std::size_t colon = spec.find(':');
  if (colon == std::string::npos) return std::nullopt;
  OsimMuscleReference reference;
  reference.file = io::trimWhitespace(spec.substr(0, colon));
  const std::string extension = detail::toLower(std::filesystem::path(reference.file).extension().string());
  if (extension != ".osim") return std::nullopt;
  std::stringstream names(spec.substr(colon + 1));
  for (std::string name; std::getline(names, name, ',');) {
    name = io::trimWhitespace(name);
    if (name.empty()) throw ModelError("\"" + io::trimWhitespace(spec) + "\": an empty muscle name; expected \"FILE.osim: MUSCLE, MUSCLE, …\"");
    reference.muscles.push_back(name);
  }
  if (reference.muscles.empty() || spec.back() == ',')
    throw ModelError("\"" + io::trimWhitespace(spec) + "\": no muscle name after ':' or a stray ','; expected \"FILE.osim: MUSCLE, …\"");
  return reference;
}

}  // namespace rbfmuscle
