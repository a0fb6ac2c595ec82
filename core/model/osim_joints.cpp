// SPDX-License-Identifier: Apache-2.0
#include "model/osim_joints.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "io/text.h"

namespace rbfmuscle::detail {
namespace {

using tinyxml2::XMLElement;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr const char* kAxisNames[6] = {"rotation1", "rotation2", "rotation3", "translation1", "translation2", "translation3"};

const XMLElement* child(const XMLElement& e, const char* name) { return e.FirstChildElement(name); }

/// A transform axis's function as read: value = slope · q + intercept (model units).
struct ParsedFunction {
  bool linear = false;  ///< LinearFunction (needs a coordinate); else a Constant (intercept only)
  double slope = 0.0;
  double intercept = 0.0;
};

/// Reads joints through the model file's XML, whose typed reads name the file and line in errors.
class OsimJointReader {
 public:
  explicit OsimJointReader(const OsimXml& xml) : xml_(xml) {}

  void readJoint(const OsimJoint& j, SkeletonBody& out, SkeletonDescription& d) const;

 private:
  void readCustomJoint(const OsimJoint& j, const std::vector<std::pair<std::string, const XMLElement*>>& coordinates,
                       SkeletonBody& out, SkeletonDescription& d) const;
  /// The six TransformAxis elements of a CustomJoint, rotation1 … translation3.
  std::array<const XMLElement*, 6> findTransformAxes(const XMLElement& joint) const;
  /// An axis's function element (3.x: inside <function>; 4.x: its child), checked; null without one.
  const XMLElement* findAxisFunction(const XMLElement& axis) const;
  /// The axis's function as the skeleton reads it (coordinate index not yet set).
  AxisFunction readAxisFunction(const XMLElement& axis, const XMLElement* function, const std::string& coordinate) const;
  std::vector<std::pair<std::string, const XMLElement*>> readCoordinateElements(const XMLElement& joint) const;
  int addCoordinate(const XMLElement* element, const std::string& name, CoordinateMotion motion,
                    const std::string& joint, SkeletonDescription& d) const;
  ParsedFunction readFunction(const XMLElement& axis, const XMLElement& function) const;

  const OsimXml& xml_;
};

std::vector<std::pair<std::string, const XMLElement*>> OsimJointReader::readCoordinateElements(const XMLElement& joint) const {
  std::vector<std::pair<std::string, const XMLElement*>> out;
  const XMLElement* list = nullptr;
  if (const XMLElement* set = child(joint, "CoordinateSet")) list = child(*set, "objects");  // 3.x
  if (!list) list = child(joint, "coordinates");                                            // 4.x
  if (!list) return out;
  for (const XMLElement* c = list->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (std::strcmp(c->Name(), "Coordinate") != 0) xml_.fail(c, "expected <Coordinate>");
    const char* name = c->Attribute("name");
    if (!name || !*name) xml_.fail(c, "missing attribute 'name'");
    out.emplace_back(name, c);
  }
  return out;
}

int OsimJointReader::addCoordinate(const XMLElement* element, const std::string& name, CoordinateMotion motion,
                              const std::string& joint, SkeletonDescription& d) const {
  for (const CoordinateInfo& c : d.coordinates)
    if (c.name == name) xml_.fail(element, "a second coordinate named '" + name + "' (also in joint '" + c.joint + "')");
  CoordinateInfo c;
  c.name = name;
  c.motion = motion;
  c.joint = joint;
  if (element) {
    const double scale = motion == CoordinateMotion::kTranslational ? xml_.getLengthToMm() : 1.0;
    const auto range = xml_.numbers(*element, "range", 2, {-kInfinity, kInfinity});
    c.range_min = scale * range[0];
    c.range_max = scale * range[1];
    c.default_value = scale * xml_.number(*element, "default_value", 0.0);
  }
  d.coordinates.push_back(c);
  return static_cast<int>(d.coordinates.size()) - 1;
}

/// A LinearFunction or a Constant, also inside a MultiplierFunction; values in model units.
ParsedFunction OsimJointReader::readFunction(const XMLElement& axis, const XMLElement& function) const {
  const std::string type = function.Name();
  ParsedFunction f;
  if (type == "LinearFunction") {
    const auto c = xml_.numbers(function, "coefficients", 2, {});
    f.linear = true;
    f.slope = c[0];
    f.intercept = c[1];
    return f;
  }
  if (type == "Constant") {
    f.intercept = xml_.number(function, "value", 0.0);
    return f;
  }
  if (type == "MultiplierFunction") {
    const double scale = xml_.number(function, "scale", 1.0);
    const XMLElement* inner = nullptr;
    if (const XMLElement* wrapper = child(function, "function")) inner = wrapper->FirstChildElement();
    if (!inner)
      for (const XMLElement* c = function.FirstChildElement(); c && !inner; c = c->NextSiblingElement())
        if (std::strcmp(c->Name(), "scale") != 0) inner = c;
    if (!inner) xml_.fail(&function, "has no function to multiply");
    const std::string inner_type = inner->Name();
    if (inner_type != "LinearFunction" && inner_type != "Constant")
      xml_.fail(inner, "in " + describeElement(axis) + ": a MultiplierFunction of a " + inner_type +
                           " couples its coordinate non-linearly; only LinearFunction and Constant (also inside a "
                           "MultiplierFunction) are supported");
    ParsedFunction g = readFunction(axis, *inner);
    g.slope *= scale;
    g.intercept *= scale;
    return g;
  }
  xml_.fail(&function, "in " + describeElement(axis) + ": function type " + type +
                           " is not supported (expected LinearFunction or Constant, also inside a MultiplierFunction)");
}

void OsimJointReader::readJoint(const OsimJoint& j, SkeletonBody& out, SkeletonDescription& d) const {
  const XMLElement& e = *j.element;
  out.joint_name = j.name;
  out.X_PF = j.X_PF;
  out.X_BM = j.X_BM;
  if (xml_.flag(e, "reverse", false))
    xml_.fail(child(e, "reverse"), "reversed joints are not supported (the joint must move the child body '" + j.child +
                                       "' relative to the parent '" + j.parent + "')");
  const auto coordinates = readCoordinateElements(e);
  if (j.type == "WeldJoint") {
    if (!coordinates.empty()) xml_.fail(coordinates.front().second, "a WeldJoint has no coordinates");
    out.joint_kind = JointKind::kWeld;
    return;
  }
  if (j.type == "PinJoint") {
    if (coordinates.size() != 1)
      xml_.fail(&e, "a PinJoint has one coordinate, found " + std::to_string(coordinates.size()));
    out.joint_kind = JointKind::kPin;
    out.pin_axis = Eigen::Vector3d::UnitZ();
    out.coordinates.push_back(addCoordinate(coordinates[0].second, coordinates[0].first, CoordinateMotion::kRotational, j.name, d));
    return;
  }
  if (j.type != "CustomJoint")
    xml_.fail(&e, "joint type " + j.type + " is not supported (expected CustomJoint, PinJoint or WeldJoint)");
  readCustomJoint(j, coordinates, out, d);
}

std::array<const XMLElement*, 6> OsimJointReader::findTransformAxes(const XMLElement& joint) const {
  const XMLElement* st = child(joint, "SpatialTransform");
  if (!st) xml_.fail(&joint, "a CustomJoint needs a <SpatialTransform>");
  std::array<const XMLElement*, 6> axes{};
  for (const XMLElement* a = st->FirstChildElement("TransformAxis"); a; a = a->NextSiblingElement("TransformAxis")) {
    const char* name = a->Attribute("name");
    int k = -1;
    for (int i = 0; i < 6; ++i)
      if (name && std::strcmp(name, kAxisNames[i]) == 0) k = i;
    if (k < 0) xml_.fail(a, "expected TransformAxis named rotation1, rotation2, rotation3, translation1, translation2 or translation3");
    if (axes[static_cast<size_t>(k)]) xml_.fail(a, std::string("a second TransformAxis ") + kAxisNames[k]);
    axes[static_cast<size_t>(k)] = a;
  }
  for (int i = 0; i < 6; ++i)
    if (!axes[static_cast<size_t>(i)]) xml_.fail(st, std::string("missing TransformAxis ") + kAxisNames[i]);
  return axes;
}

const XMLElement* OsimJointReader::findAxisFunction(const XMLElement& axis) const {
  const XMLElement* function = nullptr;
  if (const XMLElement* wrapper = child(axis, "function")) function = wrapper->FirstChildElement();
  if (!function)
    for (const XMLElement* c = axis.FirstChildElement(); c && !function; c = c->NextSiblingElement())
      if (std::strcmp(c->Name(), "coordinates") != 0 && std::strcmp(c->Name(), "axis") != 0) function = c;
  if (function) readFunction(axis, *function);  // refuses an unsupported type before anything else is said
  return function;
}

AxisFunction OsimJointReader::readAxisFunction(const XMLElement& axis, const XMLElement* function,
                                          const std::string& coordinate) const {
  AxisFunction f;
  if (!function) {
    if (!coordinate.empty()) xml_.fail(&axis, "names coordinate '" + coordinate + "' but has no function");
    return f;
  }
  const ParsedFunction parsed = readFunction(axis, *function);
  f.slope = parsed.slope;
  f.intercept = parsed.intercept;
  if (parsed.linear && coordinate.empty())
    xml_.fail(function, "in " + describeElement(axis) + ": a LinearFunction needs a coordinate, the axis names none");
  if (!parsed.linear && !coordinate.empty())
    xml_.fail(function, "in " + describeElement(axis) + ": names coordinate '" + coordinate +
                            "' but its function is a Constant (the coordinate would move nothing)");
  if (parsed.linear && f.slope == 0.0)
    xml_.fail(function, "in " + describeElement(axis) + ": slope 0 (coordinate '" + coordinate + "' would move nothing)");
  return f;
}

void OsimJointReader::readCustomJoint(const OsimJoint& j, const std::vector<std::pair<std::string, const XMLElement*>>& coordinates,
                                 SkeletonBody& out, SkeletonDescription& d) const {
  const XMLElement& e = *j.element;
  out.joint_kind = JointKind::kSpatial;
  const std::array<const XMLElement*, 6> axes = findTransformAxes(e);
  std::array<const XMLElement*, 6> functions{};  // 3.x: inside <function>; 4.x: the axis's child
  for (size_t i = 0; i < 6; ++i) functions[i] = findAxisFunction(*axes[i]);

  // Which axis each coordinate drives (at most one).
  std::map<std::string, int> driven_axis;
  std::vector<std::string> axis_coordinate(6);
  for (int i = 0; i < 6; ++i) {
    const XMLElement& a = *axes[static_cast<size_t>(i)];
    const std::vector<std::string> names = io::splitWords(xml_.text(a, "coordinates"));
    if (names.size() > 1)
      xml_.fail(&a, "is driven by " + std::to_string(names.size()) + " coordinates; at most one per axis is supported");
    const Eigen::Vector3d v = xml_.vec3(a, "axis", Eigen::Vector3d::Zero());
    if (!(v.norm() > 1e-12)) xml_.fail(child(a, "axis") ? child(a, "axis") : &a, "zero-length axis");
    out.axes[static_cast<std::size_t>(i)] = v.normalized();
    if (names.empty()) continue;
    const auto [it, inserted] = driven_axis.emplace(names[0], i);
    if (!inserted)
      xml_.fail(&a, "coordinate '" + names[0] + "' also drives TransformAxis " + kAxisNames[it->second] + " (line " +
                        std::to_string(axes[static_cast<size_t>(it->second)]->GetLineNum()) +
                        "): a coordinate coupled into two transform axes is not supported");
    axis_coordinate[static_cast<std::size_t>(i)] = names[0];
  }
  for (int group = 0; group < 6; group += 3)
    for (int a = group; a < group + 3; ++a)
      for (int b = a + 1; b < group + 3; ++b)
        if (out.axes[static_cast<std::size_t>(a)].cross(out.axes[static_cast<std::size_t>(b)]).norm() < 1e-5)
          xml_.fail(axes[static_cast<size_t>(b)],
                    std::string("axis is collinear with ") + kAxisNames[a] + "'s; the axes of a CustomJoint must be independent");

  // Coordinates in the joint's order, then any an axis names without declaring.
  std::vector<std::pair<std::string, const XMLElement*>> ordered = coordinates;
  for (const std::string& name : axis_coordinate)
    if (!name.empty() && std::none_of(ordered.begin(), ordered.end(), [&](const auto& c) { return c.first == name; }))
      ordered.emplace_back(name, nullptr);
  for (const auto& [name, element] : ordered) {
    const auto it = driven_axis.find(name);
    if (it == driven_axis.end())
      xml_.fail(element, "coordinate '" + name + "' drives no TransformAxis of " + describeElement(e) + " (it would move nothing)");
    out.coordinates.push_back(addCoordinate(
        element, name, it->second < 3 ? CoordinateMotion::kRotational : CoordinateMotion::kTranslational, j.name, d));
  }

  for (size_t i = 0; i < 6; ++i) {
    const std::string& coordinate = axis_coordinate[i];
    AxisFunction f = readAxisFunction(*axes[i], functions[i], coordinate);
    f.coordinate = -1;
    if (!coordinate.empty())
      for (int index : out.coordinates)
        if (d.coordinates[static_cast<std::size_t>(index)].name == coordinate) f.coordinate = index;
    if (i >= 3) f.intercept *= xml_.getLengthToMm();  // translation values: model units → mm; slopes stay (mm per mm)
    out.functions[i] = f;
  }
}

}  // namespace

void readOsimJoint(const OsimXml& xml, const OsimJoint& j, SkeletonBody& out, SkeletonDescription& d) {
  OsimJointReader(xml).readJoint(j, out, d);
}

}  // namespace rbfmuscle::detail
