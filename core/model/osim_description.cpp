// SPDX-License-Identifier: Apache-2.0
#include "model/osim_description.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "io/text.h"
#include "model/model_error.h"
#include "model/osim_joints.h"
#include "model/osim_xml.h"
#include "model/urdf_description.h"

namespace rbfmuscle::detail {
namespace {

namespace fs = std::filesystem;
using tinyxml2::XMLElement;

constexpr int kMaxFrameDepth = 16;  ///< frames attached to frames, at most this deep

/// Rotation from OpenSim's body-fixed XYZ angles (rad): Rx(a) · Ry(b) · Rz(c).
Eigen::Matrix3d bodyFixedXYZ(const Eigen::Vector3d& a) {
  return (Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

const XMLElement* child(const XMLElement& e, const char* name) { return e.FirstChildElement(name); }

struct OsimBody {
  std::string name;
  const XMLElement* element = nullptr;
  bool ground = false;
};

/// A resolved frame: the body it is fixed to and its pose there (mm).
struct Frame {
  std::string body;
  Eigen::Isometry3d X_BF = Eigen::Isometry3d::Identity();
};

class OsimReader : public OsimXml {
 public:
  explicit OsimReader(std::string path) : OsimXml(std::move(path)) {}
  OsimReader(std::string path, const std::string& xml_text) : OsimXml(std::move(path), xml_text) {}

  SkeletonDescription read();

 private:
  /// Pose (mm) from a translation and body-fixed XYZ angles.
  Eigen::Isometry3d pose(const Eigen::Vector3d& translation_model, const Eigen::Vector3d& angles) const {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = bodyFixedXYZ(angles);
    X.translation() = getLengthToMm() * translation_model;
    return X;
  }

  void checkConstraints(const XMLElement& model);
  void collectBodies(const XMLElement& model);
  void collectJoints(const XMLElement& model);
  Frame resolveFrame(const XMLElement& joint, const XMLElement* frames, const std::string& path,
                     const XMLElement* socket, int depth) const;
  void readMassProperties(const OsimBody& b, SkeletonBody& out) const;
  void readGeometry(const OsimBody& b, SkeletonBody& out) const;
  void addMesh(const XMLElement& where, const std::string& file, const Eigen::Isometry3d& X_BM,
               const Eigen::Vector3d& scale, std::vector<BodyMesh>& out) const;
  std::string resolveGeometryPath(const XMLElement& where, const std::string& file) const;

  std::vector<OsimBody> bodies_;
  std::vector<OsimJoint> joints_;
  std::map<std::string, const XMLElement*> body_frames_;  ///< PhysicalOffsetFrames in bodies' components
};

void OsimReader::checkConstraints(const XMLElement& model) {
  const XMLElement* set = child(model, "ConstraintSet");
  const XMLElement* objects = set ? child(*set, "objects") : nullptr;
  if (!objects) return;
  for (const XMLElement* c = objects->FirstChildElement(); c; c = c->NextSiblingElement()) {
    // OpenSim 3.x: isDisabled; 4.x: isEnforced. A constraint switched off constrains nothing.
    if (flag(*c, "isDisabled", false) || !flag(*c, "isEnforced", true)) continue;
    fail(c, "constraints are not supported: the skeleton is a tree of joints driven by a prescribed motion "
            "(give the coupled coordinates in the motion file instead)");
  }
}

void OsimReader::collectBodies(const XMLElement& model) {
  std::set<std::string> names;
  const auto add = [&](const XMLElement& e, bool ground) {
    OsimBody b;
    b.element = &e;
    const char* name = e.Attribute("name");
    if (!name || !*name) fail(&e, "missing attribute 'name'");
    b.name = name;
    b.ground = ground || b.name == "ground";
    if (!names.insert(b.name).second) fail(&e, "a second body named '" + b.name + "'");
    if (bodies_.size() == kMaxSkeletonBodies)
      fail(&e, "more than the " + std::to_string(kMaxSkeletonBodies) + " bodies a skeleton may have");
    bodies_.push_back(b);
    if (const XMLElement* components = child(e, "components"))
      for (const XMLElement* f = components->FirstChildElement("PhysicalOffsetFrame"); f;
           f = f->NextSiblingElement("PhysicalOffsetFrame"))
        if (const char* frame_name = f->Attribute("name")) body_frames_[frame_name] = f;
  };
  for (const char* tag : {"Ground", "ground"})
    if (const XMLElement* g = child(model, tag)) add(*g, true);
  const XMLElement* set = child(model, "BodySet");
  const XMLElement* objects = set ? child(*set, "objects") : nullptr;
  if (objects)
    for (const XMLElement* b = objects->FirstChildElement(); b; b = b->NextSiblingElement()) {
      if (std::strcmp(b->Name(), "Body") != 0) fail(b, "expected <Body> in the BodySet");
      add(*b, false);
    }
  const auto grounds = std::count_if(bodies_.begin(), bodies_.end(), [](const OsimBody& b) { return b.ground; });
  if (grounds != 1)
    fail(&model, grounds == 0 ? "no ground (expected <Ground name=\"ground\"> or a Body named 'ground')"
                              : "more than one ground");
}

Frame OsimReader::resolveFrame(const XMLElement& joint, const XMLElement* frames, const std::string& path,
                               const XMLElement* socket, int depth) const {
  if (depth > kMaxFrameDepth)
    fail(socket, "frames attached to frames nest deeper than " + std::to_string(kMaxFrameDepth) + " (a cycle?)");
  const std::string name = lastPathComponent(path);
  if (name.empty()) fail(socket, "names no frame");
  const XMLElement* offset = nullptr;
  if (frames)
    for (const XMLElement* f = frames->FirstChildElement("PhysicalOffsetFrame"); f && !offset;
         f = f->NextSiblingElement("PhysicalOffsetFrame"))
      if (const char* n = f->Attribute("name"); n && name == n) offset = f;
  const std::string* owner_body = nullptr;  // a body-component frame's ".." is its body
  if (!offset) {
    const auto it = body_frames_.find(name);
    if (it != body_frames_.end()) {
      offset = it->second;
      for (const OsimBody& b : bodies_)
        if (const XMLElement* components = child(*b.element, "components"))
          if (offset->Parent() == components) owner_body = &b.name;
    }
  }
  if (offset) {
    std::string parent_path = text(*offset, "socket_parent");
    if (parent_path.empty()) parent_path = text(*offset, "socket_parent_connectee_name");
    if (parent_path.empty()) fail(offset, "has no socket_parent");
    if ((parent_path == ".." || parent_path == "../") && owner_body) parent_path = *owner_body;
    const XMLElement* parent_socket = child(*offset, "socket_parent");
    Frame parent = resolveFrame(joint, frames, parent_path, parent_socket ? parent_socket : offset, depth + 1);
    parent.X_BF = parent.X_BF * pose(vec3(*offset, "translation", Eigen::Vector3d::Zero()),
                                     vec3(*offset, "orientation", Eigen::Vector3d::Zero()));
    return parent;
  }
  for (const OsimBody& b : bodies_)
    if (b.name == name) return Frame{b.name, Eigen::Isometry3d::Identity()};
  fail(socket, "frame '" + path + "' is neither a PhysicalOffsetFrame of " + describeElement(joint) +
                   " or of a body, nor a body or ground");
}

void OsimReader::collectJoints(const XMLElement& model) {
  // OpenSim 3.x: each body's joint nested in it.
  for (const OsimBody& b : bodies_) {
    const XMLElement* holder = child(*b.element, "Joint");
    if (!holder) continue;
    const XMLElement* e = holder->FirstChildElement();
    if (!e) continue;  // <Joint/>: ground, or a body left unconnected (found below)
    if (e->NextSiblingElement()) fail(e->NextSiblingElement(), "a body's <Joint> holds one joint, found a second");
    OsimJoint j;
    j.element = e;
    j.type = e->Name();
    j.name = e->Attribute("name") ? e->Attribute("name") : "";
    j.child = b.name;
    j.parent = text(*e, "parent_body");
    if (j.parent.empty()) fail(e, "missing <parent_body>");
    j.X_PF = pose(vec3(*e, "location_in_parent", Eigen::Vector3d::Zero()),
                  vec3(*e, "orientation_in_parent", Eigen::Vector3d::Zero()));
    j.X_BM = pose(vec3(*e, "location", Eigen::Vector3d::Zero()), vec3(*e, "orientation", Eigen::Vector3d::Zero()));
    joints_.push_back(j);
  }
  // OpenSim 4.x: a JointSet whose joints name their frames.
  const XMLElement* set = child(model, "JointSet");
  const XMLElement* objects = set ? child(*set, "objects") : nullptr;
  if (!objects) return;
  for (const XMLElement* e = objects->FirstChildElement(); e; e = e->NextSiblingElement()) {
    OsimJoint j;
    j.element = e;
    j.type = e->Name();
    j.name = e->Attribute("name") ? e->Attribute("name") : "";
    const XMLElement* frames = child(*e, "frames");
    const auto socket = [&](const char* name) -> const XMLElement* {
      if (const XMLElement* s = child(*e, name)) return s;
      return child(*e, (std::string(name) + "_connectee_name").c_str());
    };
    const XMLElement* parent_socket = socket("socket_parent_frame");
    const XMLElement* child_socket = socket("socket_child_frame");
    if (!parent_socket || !child_socket)
      fail(e, "expected <socket_parent_frame> and <socket_child_frame>");
    const Frame parent = resolveFrame(*e, frames, parent_socket->GetText() ? parent_socket->GetText() : "", parent_socket, 0);
    const Frame child_frame = resolveFrame(*e, frames, child_socket->GetText() ? child_socket->GetText() : "", child_socket, 0);
    j.parent = parent.body;
    j.child = child_frame.body;
    j.X_PF = parent.X_BF;
    j.X_BM = child_frame.X_BF;
    joints_.push_back(j);
  }
}

void OsimReader::readMassProperties(const OsimBody& b, SkeletonBody& out) const {
  const XMLElement& e = *b.element;
  const double mass = number(e, "mass", 0.0);
  if (mass < 0.0)
    fail(child(e, "mass"), "body '" + b.name + "': " + findMassPropertiesProblem(mass, Eigen::Matrix3d::Zero()));
  if (mass == 0.0) {  // massless (ground, frames): kinematics alone
    out.mass_kg = kDefaultLinkMass_kg;
    out.inertia_B_kgmm2 = kDefaultLinkMass_kg * Eigen::Matrix3d::Identity();
    return;
  }
  out.mass_kg = mass;
  const Eigen::Vector3d c = getLengthToMm() * vec3(e, "mass_center", Eigen::Vector3d::Zero());
  Eigen::Matrix3d I_C;  // about the mass centre, in body axes, model units
  if (child(e, "inertia")) {  // 4.x: Ixx Iyy Izz Ixy Ixz Iyz
    const auto v = numbers(e, "inertia", 6, {});
    I_C << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
  } else {
    const double xx = number(e, "inertia_xx", 0), yy = number(e, "inertia_yy", 0), zz = number(e, "inertia_zz", 0);
    const double xy = number(e, "inertia_xy", 0), xz = number(e, "inertia_xz", 0), yz = number(e, "inertia_yz", 0);
    I_C << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  }
  if (!(c.cwiseAbs().maxCoeff() <= kMaxOsimOffset_mm))
    fail(child(e, "mass_center"), "mass centre more than 1000 m from the body's origin: expected a point on the body");
  const double to_m = getLengthToMm() / 1000.0;
  const std::string problem = findMassPropertiesProblem(mass, to_m * to_m * I_C);
  if (!problem.empty()) fail(&e, "body '" + b.name + "': " + problem);
  out.com_B_mm = c;
  out.inertia_B_kgmm2 = getLengthToMm() * getLengthToMm() * I_C + mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

std::string OsimReader::resolveGeometryPath(const XMLElement& where, const std::string& file) const {
  std::string name = io::trimWhitespace(file);
  std::replace(name.begin(), name.end(), '\\', '/');
  const fs::path as_written(name);
  const fs::path dir = fs::absolute(fs::path(getPath())).parent_path();
  std::vector<fs::path> candidates;
  candidates.push_back(as_written.is_absolute() ? as_written : dir / as_written);
  candidates.push_back(dir / "Geometry" / as_written.filename());
  candidates.push_back(dir / "geometry" / as_written.filename());
  std::string tried;
  for (const fs::path& p : candidates) {
    const fs::path normal = p.lexically_normal();
    std::error_code ec;  // a name too long for the system is a file not found, not an exception
    if (fs::is_regular_file(normal, ec)) return normal.string();
    tried += (tried.empty() ? "" : ", ") + normal.string();
  }
  fail(&where, "geometry file '" + file + "' not found (looked for " + tried + ")");
}

void OsimReader::addMesh(const XMLElement& where, const std::string& file, const Eigen::Isometry3d& X_BM,
                         const Eigen::Vector3d& scale, std::vector<BodyMesh>& out) const {
  const std::string name = io::trimWhitespace(file);
  if (name.empty()) return;
  const std::string ext = toLower(fs::path(name).extension().string());
  if (ext != ".vtp" && ext != ".stl" && ext != ".obj" && ext != ".ply")
    fail(&where, "geometry file '" + file + "': extension '" + ext + "' is not supported (expected .vtp, .stl, .obj or .ply)");
  BodyMesh m;
  m.path = resolveGeometryPath(where, file);
  m.X_BM = X_BM;
  m.scale_to_mm = getLengthToMm() * scale;
  m.collision = false;
  out.push_back(std::move(m));
}

void OsimReader::readGeometry(const OsimBody& b, SkeletonBody& out) const {
  const XMLElement& e = *b.element;
  // OpenSim 3.x: VisibleObject.
  if (const XMLElement* visible = child(e, "VisibleObject")) {
    const Eigen::Vector3d outer_scale = vec3(*visible, "scale_factors", Eigen::Vector3d::Ones());
    const auto outer = numbers(*visible, "transform", 6, {0, 0, 0, 0, 0, 0});
    const Eigen::Isometry3d X_outer = pose({outer[3], outer[4], outer[5]}, {outer[0], outer[1], outer[2]});
    if (const XMLElement* list = child(*visible, "geometry_files"))
      for (const std::string& file : io::splitWords(list->GetText() ? list->GetText() : ""))
        addMesh(*list, file, X_outer, outer_scale, out.meshes);
    const XMLElement* set = child(*visible, "GeometrySet");
    const XMLElement* objects = set ? child(*set, "objects") : nullptr;
    if (objects)
      for (const XMLElement* g = objects->FirstChildElement("DisplayGeometry"); g;
           g = g->NextSiblingElement("DisplayGeometry")) {
        const auto inner = numbers(*g, "transform", 6, {0, 0, 0, 0, 0, 0});
        const Eigen::Isometry3d X_inner = pose({inner[3], inner[4], inner[5]}, {inner[0], inner[1], inner[2]});
        const Eigen::Vector3d scale = outer_scale.cwiseProduct(vec3(*g, "scale_factors", Eigen::Vector3d::Ones()));
        addMesh(*g, text(*g, "geometry_file"), X_outer * X_inner, scale, out.meshes);
      }
  }
  // OpenSim 4.x: attached_geometry of the body and of frames among its components.
  const auto attached = [&](const XMLElement& owner, const Eigen::Isometry3d& X_BF) {
    const XMLElement* list = child(owner, "attached_geometry");
    if (!list) return;
    for (const XMLElement* g = list->FirstChildElement("Mesh"); g; g = g->NextSiblingElement("Mesh")) {
      const std::string frame = text(*g, "socket_frame");
      if (!frame.empty() && frame != ".." && frame != "../" && lastPathComponent(frame) != lastPathComponent(owner.Attribute("name") ? owner.Attribute("name") : ""))
        fail(g, "socket_frame '" + frame + "': a mesh must be attached to the frame that lists it");
      addMesh(*g, text(*g, "mesh_file"), X_BF, vec3(*g, "scale_factors", Eigen::Vector3d::Ones()), out.meshes);
    }
  };
  attached(e, Eigen::Isometry3d::Identity());
  if (const XMLElement* components = child(e, "components"))
    for (const XMLElement* f = components->FirstChildElement("PhysicalOffsetFrame"); f;
         f = f->NextSiblingElement("PhysicalOffsetFrame")) {
      if (!child(*f, "attached_geometry")) continue;
      const std::string parent = text(*f, "socket_parent");
      if (!(parent == ".." || parent == "../" || lastPathComponent(parent) == b.name))
        fail(f, "a frame carrying geometry among a body's components must be attached to that body (socket_parent '..')");
      attached(*f, pose(vec3(*f, "translation", Eigen::Vector3d::Zero()), vec3(*f, "orientation", Eigen::Vector3d::Zero())));
    }
}

SkeletonDescription OsimReader::read() {
  const XMLElement* model = &getModel();
  checkConstraints(*model);
  collectBodies(*model);
  collectJoints(*model);

  SkeletonDescription d;
  d.name = model->Attribute("name") ? model->Attribute("name") : fs::path(getPath()).stem().string();
  d.path = getPath();
  d.format = "OpenSim model";

  // Each body but ground is the child of exactly one joint.
  std::map<std::string, const OsimJoint*> joint_of;
  for (const OsimJoint& j : joints_) {
    const auto known = [&](const std::string& name) {
      return std::any_of(bodies_.begin(), bodies_.end(), [&](const OsimBody& b) { return b.name == name; });
    };
    if (!known(j.parent)) fail(j.element, "parent body '" + j.parent + "' is not a body of the model");
    if (!known(j.child)) fail(j.element, "child body '" + j.child + "' is not a body of the model");
    if (j.child == j.parent) fail(j.element, "joins body '" + j.child + "' to itself");
    const OsimBody& child_body = *std::find_if(bodies_.begin(), bodies_.end(), [&](const OsimBody& b) { return b.name == j.child; });
    if (child_body.ground) fail(j.element, "moves ground (reversed joints are not supported)");
    if (!joint_of.emplace(j.child, &j).second)
      fail(j.element, "body '" + j.child + "' already hangs on joint '" + joint_of[j.child]->name +
                          "' (line " + std::to_string(joint_of[j.child]->element->GetLineNum()) +
                          "): closed loops are not supported");
  }
  for (const OsimBody& b : bodies_)
    if (!b.ground && joint_of.count(b.name) == 0) fail(b.element, "body '" + b.name + "' has no joint to a parent body");

  // Depth first from ground; bodies in file order among siblings.
  const OsimBody& ground = *std::find_if(bodies_.begin(), bodies_.end(), [](const OsimBody& b) { return b.ground; });
  std::vector<std::pair<const OsimBody*, int>> stack{{&ground, -1}};
  std::set<std::string> placed;
  while (!stack.empty()) {  // each body is pushed once: at most bodies_.size() rounds
    const auto [body, parent] = stack.back();
    stack.pop_back();
    placed.insert(body->name);
    SkeletonBody out;
    out.name = body->name;
    out.parent = parent;
    if (parent >= 0) readOsimJoint(*this, *joint_of.at(body->name), out, d);
    readMassProperties(*body, out);
    readGeometry(*body, out);
    d.bodies.push_back(std::move(out));
    const int self = static_cast<int>(d.bodies.size()) - 1;
    for (auto it = bodies_.rbegin(); it != bodies_.rend(); ++it) {
      const auto j = joint_of.find(it->name);
      if (j != joint_of.end() && j->second->parent == body->name) stack.emplace_back(&*it, self);
    }
  }
  for (const OsimBody& b : bodies_)
    if (placed.count(b.name) == 0)
      fail(b.element, "body '" + b.name + "' is not connected to ground (its joints form a loop apart from it)");
  return d;
}

}  // namespace

SkeletonDescription readOsim(const std::string& path) { return OsimReader(path).read(); }

SkeletonDescription parseOsim(const std::string& text, const std::string& path) {
  return OsimReader(path, text).read();
}

}  // namespace rbfmuscle::detail
