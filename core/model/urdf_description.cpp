// SPDX-License-Identifier: Apache-2.0
#include "model/urdf_description.h"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "io/file_checks.h"
#include "io/format_number.h"

namespace rbfmuscle::detail {
namespace {

namespace fs = std::filesystem;

constexpr double kMetresToMm = 1000.0;

/// Collects urdfdom's console_bridge messages while it parses, so that the
/// ModelError can say why parsing failed instead of printing to stderr.
class CaptureLog : public console_bridge::OutputHandler {
 public:
  CaptureLog() { console_bridge::useOutputHandler(this); }
  ~CaptureLog() override { console_bridge::restorePreviousOutputHandler(); }
  CaptureLog(const CaptureLog&) = delete;
  CaptureLog& operator=(const CaptureLog&) = delete;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) text_ += (text_.empty() ? "" : "; ") + text;
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) has_error_ = true;
  }
  const std::string& text() const { return text_; }
  bool hasError() const { return has_error_; }

 private:
  std::string text_;
  bool has_error_ = false;
};

std::string where(const std::string& urdf_path, const std::string& what);

/// Refuses a pose whose numbers are not finite or whose translation is implausible.
void checkPose(const std::string& urdf_path, const urdf::Pose& pose, const std::string& owner) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  const double p[3] = {pose.position.x, pose.position.y, pose.position.z};
  for (double v : p)
    if (!std::isfinite(v) || std::abs(v) > kMaxUrdfTranslation_m)
      throw ModelError(where(urdf_path, owner + ": origin xyz " + io::formatNumber(p[0]) + " " + io::formatNumber(p[1]) +
                                            " " + io::formatNumber(p[2]) + " m: expected finite values of magnitude at most " +
                                            io::formatNumber(kMaxUrdfTranslation_m) + " m"));
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(w) ||
      !(x * x + y * y + z * z + w * w > 0))
    throw ModelError(where(urdf_path, owner + ": origin rpy is not a finite rotation"));
}

Eigen::Isometry3d toIsometry_mm(const urdf::Pose& pose) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  X.translation() = kMetresToMm * Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return X;
}

std::string where(const std::string& urdf_path, const std::string& what) {
  return "URDF " + urdf_path + ": " + what;
}

/// Mesh path: `file://` prefix dropped; relative paths are relative to the URDF's directory.
std::string resolveMeshPath(const std::string& urdf_path, const std::string& link,
                            const std::string& filename) {
  std::string name = filename;
  if (name.rfind("file://", 0) == 0) name = name.substr(7);
  if (name.find("://") != std::string::npos)
    throw ModelError(where(urdf_path, "link '" + link + "': mesh '" + filename +
                                          "' uses a URI scheme; give a path relative to the "
                                          "URDF file or an absolute path"));
  fs::path p(name);
  if (p.is_relative()) p = fs::absolute(fs::path(urdf_path)).parent_path() / p;
  p = p.lexically_normal();
  std::error_code ec;  // a name too long for the system is a file that does not exist, not an exception
  if (!fs::is_regular_file(p, ec))
    throw ModelError(where(urdf_path, "link '" + link + "': mesh file '" + p.string() +
                                          "' (from filename=\"" + filename + "\") does not exist"));
  return p.string();
}

void addMesh(const std::string& urdf_path, const std::string& link, const urdf::Pose& origin,
             const urdf::GeometrySharedPtr& geometry, bool collision, std::vector<BodyMesh>& out) {
  if (!geometry || geometry->type != urdf::Geometry::MESH) return;  // primitives are not bone meshes
  const auto& mesh = static_cast<const urdf::Mesh&>(*geometry);
  const double scale[3] = {mesh.scale.x, mesh.scale.y, mesh.scale.z};
  for (double v : scale)
    if (!std::isfinite(v) || !(v >= kMinUrdfMeshScale && v <= kMaxUrdfMeshScale))
      throw ModelError(where(urdf_path, "link '" + link + "': mesh '" + mesh.filename + "' has scale " +
                                            io::formatNumber(scale[0]) + " " + io::formatNumber(scale[1]) + " " +
                                            io::formatNumber(scale[2]) + ": expected each factor from " +
                                            io::formatNumber(kMinUrdfMeshScale) + " to " + io::formatNumber(kMaxUrdfMeshScale) +
                                            " (metres per mesh unit; 0.001 for a mesh in mm; a negative factor "
                                            "would mirror the bone and turn it inside out)"));
  checkPose(urdf_path, origin, "link '" + link + "': mesh '" + mesh.filename + "'");
  BodyMesh m;
  m.path = resolveMeshPath(urdf_path, link, mesh.filename);
  m.X_BM = toIsometry_mm(origin);
  m.scale_to_mm = kMetresToMm * Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z);
  m.collision = collision;
  out.push_back(std::move(m));
}

void readInertial(const urdf::Link& in, UrdfLink& out) {
  if (!in.inertial) {
    out.mass_kg = kDefaultLinkMass_kg;
    out.inertia_B_kgmm2 = kDefaultLinkMass_kg * Eigen::Matrix3d::Identity();
    return;
  }
  const urdf::Inertial& i = *in.inertial;
  const double values[] = {i.mass, i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz};
  for (double v : values)
    if (!std::isfinite(v))
      throw ModelError("link '" + in.name + "': <inertial> holds a non-finite mass or inertia");
  out.mass_kg = i.mass;
  const Eigen::Isometry3d X_BC = toIsometry_mm(i.origin);
  Eigen::Matrix3d I_C;  // about the mass centre, in the inertial frame C, kg·m²
  I_C << i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz;
  const std::string problem = findMassPropertiesProblem(i.mass, I_C);
  if (!problem.empty()) throw ModelError("link '" + in.name + "': <inertial> " + problem);
  const Eigen::Vector3d c = X_BC.translation();
  // Rotate into link axes, m² → mm², then the parallel-axis shift to the origin.
  out.com_B_mm = c;
  out.inertia_B_kgmm2 = X_BC.linear() * (kMetresToMm * kMetresToMm * I_C) * X_BC.linear().transpose() +
                        i.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

void addLink(const std::string& urdf_path, const urdf::Link& link, int parent,
             const urdf::Joint* joint, UrdfDescription& out) {
  UrdfLink l;
  l.name = link.name;
  l.parent = parent;
  if (joint) {
    checkPose(urdf_path, joint->parent_to_joint_origin_transform, "joint '" + joint->name + "'");
    l.joint_name = joint->name;
    l.X_PJ = toIsometry_mm(joint->parent_to_joint_origin_transform);
    switch (joint->type) {
      case urdf::Joint::FIXED:
        l.joint_kind = UrdfJointKind::kFixed;
        break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS: {
        l.joint_kind = UrdfJointKind::kRevolute;
        const Eigen::Vector3d a(joint->axis.x, joint->axis.y, joint->axis.z);
        if (!a.allFinite())
          throw ModelError(where(urdf_path, "joint '" + joint->name + "' has a non-finite axis"));
        const double length = a.stableNorm();  // a plain norm overflows for components near 1e300
        if (!(length > 1e-12))
          throw ModelError(where(urdf_path, "joint '" + joint->name + "' has a zero axis"));
        l.axis_J = a / length;
        break;
      }
      default: {
        const char* type = joint->type == urdf::Joint::PRISMATIC  ? "prismatic"
                           : joint->type == urdf::Joint::FLOATING ? "floating"
                           : joint->type == urdf::Joint::PLANAR   ? "planar"
                                                                  : "unknown";
        throw ModelError(where(urdf_path, "joint '" + joint->name + "' has type '" + type +
                                              "'; only revolute, continuous and fixed joints are "
                                              "supported (chain one-DOF joints instead)"));
      }
    }
  }
  if (link.inertial) checkPose(urdf_path, link.inertial->origin, "link '" + link.name + "': <inertial>");
  try {
    readInertial(link, l);
  } catch (const ModelError& e) {
    throw ModelError(where(urdf_path, e.what()));
  }
  for (const auto& v : link.visual_array)
    if (v) addMesh(urdf_path, link.name, v->origin, v->geometry, false, l.meshes);
  for (const auto& c : link.collision_array)
    if (c) addMesh(urdf_path, link.name, c->origin, c->geometry, true, l.meshes);
  out.links.push_back(std::move(l));
  const int self = static_cast<int>(out.links.size()) - 1;
  for (const auto& child_joint : link.child_joints) {
    const auto child = std::find_if(link.child_links.begin(), link.child_links.end(),
                                    [&](const urdf::LinkSharedPtr& c) {
                                      return c && c->name == child_joint->child_link_name;
                                    });
    if (child == link.child_links.end())
      throw ModelError(where(urdf_path, "joint '" + child_joint->name + "' names child link '" +
                                            child_joint->child_link_name + "' that is not found"));
    addLink(urdf_path, **child, self, child_joint.get(), out);
  }
}

/// Refuses what urdfdom accepts but a kinematic tree cannot be: a link that is the child of
/// two or more joints (a closed loop; following it never ends), and links that cannot be
/// reached from the root (a cycle apart from it). Names the links and joints.
void checkTree(const std::string& urdf_path, const urdf::ModelInterface& model) {
  std::map<std::string, std::vector<const urdf::Joint*>> parents;
  for (const auto& [name, joint] : model.joints_)
    if (joint) parents[joint->child_link_name].push_back(joint.get());
  for (const auto& [child, joints] : parents) {
    if (joints.size() < 2) continue;
    std::string list;
    for (const urdf::Joint* j : joints)
      list += (list.empty() ? "" : ", ") + ("'" + j->name + "' from link '" + j->parent_link_name + "'");
    throw ModelError(where(urdf_path, "link '" + child + "' has " + std::to_string(joints.size()) +
                                          " parent joints (" + list +
                                          "); the links must form a tree, each link the child of at most one joint "
                                          "(a closed kinematic loop is not supported)"));
  }
  if (model.links_.size() > kMaxSkeletonBodies)
    throw ModelError(where(urdf_path, std::to_string(model.links_.size()) + " links, more than the " +
                                          std::to_string(kMaxSkeletonBodies) + " a skeleton may have"));
  std::set<std::string> reached;
  std::vector<const urdf::Link*> stack = {model.getRoot().get()};
  while (!stack.empty() && reached.size() <= model.links_.size()) {  // each link is pushed at most once
    const urdf::Link* link = stack.back();
    stack.pop_back();
    if (!reached.insert(link->name).second) continue;
    for (const auto& joint : link->child_joints) {
      const auto child = model.links_.find(joint->child_link_name);
      if (child != model.links_.end() && child->second && reached.count(child->first) == 0)
        stack.push_back(child->second.get());
    }
  }
  for (const auto& [name, link] : model.links_)
    if (reached.count(name) == 0)
      throw ModelError(where(urdf_path, "link '" + name + "' is not connected to the root link '" +
                                            model.getRoot()->name +
                                            "' (its joints form a loop apart from the tree, or it has no parent joint)"));
}

/// Refuses joints that close a loop of links, as urdfdom reads them (each <joint>'s first
/// <parent> and <child>). urdfdom links every joint's child into its parent by shared_ptr before
/// it checks the tree, so when it then drops the model a loop still holds itself (a leak the
/// fuzzer found: two links that are each other's parent, and a joint whose parent is its own
/// child beside a link with two parents). So every loop, through any links, is refused before
/// urdfdom reads the text: a depth-first walk from parent to child meets a link on its own path.
void checkNoLoopOfJoints(const std::string& urdf_path, const tinyxml2::XMLDocument& xml) {
  const tinyxml2::XMLElement* robot = xml.FirstChildElement("robot");
  if (!robot) return;  // urdfdom says what is missing
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> children;  // link → (joint, child link)
  for (const tinyxml2::XMLElement* joint = robot->FirstChildElement("joint"); joint;
       joint = joint->NextSiblingElement("joint")) {
    const tinyxml2::XMLElement* parent = joint->FirstChildElement("parent");
    const tinyxml2::XMLElement* child = joint->FirstChildElement("child");
    const char* parent_link = parent ? parent->Attribute("link") : nullptr;
    const char* child_link = child ? child->Attribute("link") : nullptr;
    const char* name = joint->Attribute("name");
    // urdfdom reads the text with another XML reader, which decodes an unknown entity ("&a")
    // differently: the links it joins must be the links checked here.
    for (const char* link : {parent_link, child_link})
      if (link && std::string(link).find('&') != std::string::npos)
        throw ModelError(where(urdf_path, "joint '" + std::string(name ? name : "") + "' names the link '" + link +
                                              "', with an '&' that XML readers decode differently; expected a "
                                              "link name without '&'"));
    if (parent_link && child_link) children[parent_link].emplace_back(name ? name : "", child_link);
  }
  enum class Walk { kOnPath, kDone };
  std::map<std::string, Walk> walked;
  struct Step {
    std::string link;
    size_t next_child = 0;
  };
  for (const auto& root : children) {
    if (walked.count(root.first)) continue;
    std::vector<Step> path{{root.first}};
    std::vector<std::string> joints;  // joints[i] leads from path[i] to path[i + 1]
    walked[root.first] = Walk::kOnPath;
    while (!path.empty()) {
      const auto below = children.find(path.back().link);
      if (below == children.end() || path.back().next_child == below->second.size()) {
        walked[path.back().link] = Walk::kDone;
        path.pop_back();
        if (!joints.empty()) joints.pop_back();
        continue;
      }
      const auto [joint, child] = below->second[path.back().next_child++];
      const auto seen = walked.find(child);
      if (seen == walked.end()) {
        walked[child] = Walk::kOnPath;
        joints.push_back(joint);
        path.push_back({child});
      } else if (seen->second == Walk::kOnPath) {
        size_t first = 0;
        while (path[first].link != child) ++first;
        std::string loop_joints, loop_links;
        for (size_t i = first; i < path.size(); ++i) {
          loop_joints += (i > first ? ", '" : "'") + (i + 1 < path.size() ? joints[i] : joint) + "'";
          loop_links += "'" + path[i].link + "' → ";
        }
        throw ModelError(where(urdf_path, "joints " + loop_joints + " form a closed loop of links (" + loop_links + "'" +
                                              child + "'); the links must form a tree (a closed kinematic loop is not "
                                              "supported)"));
      }
    }
  }
}

}  // namespace

SkeletonDescription describeUrdf(const UrdfDescription& urdf) {
  SkeletonDescription d;
  d.name = urdf.name;
  d.path = urdf.path;
  d.format = "URDF";
  for (const UrdfLink& link : urdf.links) {
    SkeletonBody b;
    b.name = link.name;
    b.parent = link.parent;
    b.joint_name = link.joint_name;
    b.X_PF = link.X_PJ;
    switch (link.joint_kind) {
      case UrdfJointKind::kRoot:
        b.joint_kind = JointKind::kRoot;
        b.X_PF = Eigen::Isometry3d::Identity();
        break;
      case UrdfJointKind::kFixed:
        b.joint_kind = JointKind::kWeld;
        break;
      case UrdfJointKind::kRevolute: {
        b.joint_kind = JointKind::kPin;
        b.pin_axis = link.axis_J;
        b.coordinates.push_back(static_cast<int>(d.coordinates.size()));
        CoordinateInfo c;
        c.name = link.joint_name;
        c.joint = link.joint_name;
        d.coordinates.push_back(c);
        break;
      }
    }
    b.mass_kg = link.mass_kg;
    b.com_B_mm = link.com_B_mm;
    b.inertia_B_kgmm2 = link.inertia_B_kgmm2;
    b.meshes = link.meshes;
    d.bodies.push_back(std::move(b));
  }
  return d;
}

UrdfDescription readUrdf(const std::string& path) {
  const std::string problem = io::findInputFileProblem(path, "a URDF file");
  if (!problem.empty()) throw ModelError(where(path, problem));
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (bytes > kMaxUrdfFileBytes)
    throw ModelError(where(path, std::to_string(bytes) + " bytes, more than the " + std::to_string(kMaxUrdfFileBytes) +
                                     " a URDF file may have"));
  std::ifstream in(path);
  if (!in) throw ModelError(where(path, "cannot open the file (missing or unreadable)"));
  std::stringstream text;
  text << in.rdbuf();
  return parseUrdf(text.str(), path);
}

namespace {

/// Offset of the first byte of `text` that does not start or continue a whole UTF-8 character
/// (NUL included), or npos.
size_t findInvalidUtf8(const std::string& text) {
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const size_t more = (c & 0xE0) == 0xC0 ? 1 : (c & 0xF0) == 0xE0 ? 2 : (c & 0xF8) == 0xF0 ? 3 : 0;
    if (c == 0 || (c >= 0x80 && more == 0) || i + more >= text.size()) return i;
    for (size_t k = 1; k <= more; ++k)
      if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80) return i;
    i += 1 + more;
  }
  return std::string::npos;
}

}  // namespace

UrdfDescription parseUrdf(const std::string& text, const std::string& path) {
  if (text.size() > kMaxUrdfFileBytes)
    throw ModelError(where(path, std::to_string(text.size()) + " bytes, more than the " +
                                     std::to_string(kMaxUrdfFileBytes) + " a URDF file may have"));
  // urdfdom's TinyXML 2.6 trusts a UTF-8 lead byte and reads past the end of the text when the
  // bytes it announces are missing (found by fuzz_urdf), so the text is checked first.
  const size_t bad = findInvalidUtf8(text);
  if (bad != std::string::npos)
    throw ModelError(where(path, "line " + std::to_string(1 + std::count(text.begin(), text.begin() + bad, '\n')) +
                                     ": byte " + std::to_string(bad) + " is not valid UTF-8 (expected a UTF-8 text)"));
  // urdfdom's TinyXML parses recursively and overflows the stack on deep nesting (200 000 nested
  // elements crashed, signal 11); tinyxml2 bounds the depth, so it reads the text first and
  // names the line of what is wrong.
  tinyxml2::XMLDocument xml;
  if (xml.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    throw ModelError(where(path, "line " + std::to_string(xml.ErrorLineNum()) + ": not well-formed XML: " +
                                     xml.ErrorStr()));
  checkNoLoopOfJoints(path, xml);
  urdf::ModelInterfaceSharedPtr model;
  std::string log;
  bool dropped = false;
  {
    CaptureLog capture;
    try {
      model = urdf::parseURDF(text);
    } catch (const std::exception& e) {
      throw ModelError(where(path, std::string("urdfdom could not parse it: ") + e.what()));
    }
    log = capture.text();
    dropped = capture.hasError();
  }
  // urdfdom's links hold their children by shared_ptr, so links whose joints form a cycle (refused
  // by checkTree, or met while urdfdom builds a tree it then reports) keep each other alive:
  // unlink them whenever the model is dropped, whichever check refuses it.
  struct BreakLinkCycles {
    urdf::ModelInterfaceSharedPtr model;
    ~BreakLinkCycles() {
      if (!model) return;
      for (auto& [name, link] : model->links_)
        if (link) {
          link->child_links.clear();
          link->child_joints.clear();
        }
    }
  } break_cycles{model};
  if (!model || !model->getRoot())
    throw ModelError(where(path, "urdfdom could not parse it" + (log.empty() ? "" : ": " + log)));
  // urdfdom reports an element it cannot read (an origin "nan 0 0" or "abc")
  // and returns the model without it, and without the link's other collision or visual elements:
  // a bone would silently leave the contacts.
  if (dropped) throw ModelError(where(path, "urdfdom left out what it could not read: " + log));

  checkTree(path, *model);
  UrdfDescription d;
  d.name = model->getName();
  d.path = path;
  addLink(path, *model->getRoot(), -1, nullptr, d);
  return d;
}

}  // namespace rbfmuscle::detail
