// SPDX-License-Identifier: Apache-2.0
#include "model/skeleton.h"

#include <Simbody.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "model/osim_description.h"
#include "model/skeleton_description.h"
#include "model/urdf_description.h"

namespace rbfmuscle {
namespace {

SimTK::Transform toSimTK(const Eigen::Isometry3d& X) {
  SimTK::Mat33 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = X.linear()(i, j);
  const Eigen::Vector3d& p = X.translation();
  return SimTK::Transform(SimTK::Rotation(R, true), SimTK::Vec3(p.x(), p.y(), p.z()));
}

Eigen::Isometry3d toEigen(const SimTK::Transform& X) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.linear()(i, j) = X.R().asMat33()(i, j);
    out.translation()(i) = X.p()[i];
  }
  return out;
}

/// Rotation R_JA whose Z axis is the unit vector `axis_J`: a Simbody pin turns
/// about its Z axis, so frames rotated by R_JA make it turn about the URDF axis.
Eigen::Isometry3d pinAxisFrame(const Eigen::Vector3d& axis_J) {
  const SimTK::Rotation R(SimTK::UnitVec3(axis_J.x(), axis_J.y(), axis_J.z()), SimTK::ZAxis);
  return toEigen(SimTK::Transform(R, SimTK::Vec3(0)));
}

/// The body's mass properties for Simbody. @throws ModelError naming the body when they are invalid.
SimTK::Body::Rigid makeRigidBody(const detail::SkeletonDescription& d, const detail::SkeletonBody& link) {
  try {
    SimTK::Mat33 I;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) I(i, j) = link.inertia_B_kgmm2(i, j);
    const Eigen::Vector3d& c = link.com_B_mm;
    return SimTK::Body::Rigid(SimTK::MassProperties(link.mass_kg, SimTK::Vec3(c.x(), c.y(), c.z()), SimTK::Inertia(I)));
  } catch (const std::exception& e) {
    throw ModelError(d.format + " " + d.path + ": " + (d.format == "URDF" ? "link '" : "body '") + link.name +
                     "' has invalid mass properties (mass must be positive, inertia a valid "
                     "symmetric inertia matrix): " + e.what());
  }
}

/// A spatial joint with coordinates as OpenSim builds a CustomJoint: one FunctionBased mobilizer
/// whose six functions (three rotations, three translations) take the joint's coordinates as
/// arguments, in the order of link.coordinates.
SimTK::MobilizedBodyIndex addFunctionBased(SimTK::MobilizedBody& parent, const SimTK::Body::Rigid& body,
                                           const detail::SkeletonBody& link) {
  std::vector<const SimTK::Function*> functions;
  std::vector<std::vector<int>> arguments;
  std::vector<SimTK::Vec3> axes;
  for (int i = 0; i < 6; ++i) {
    const detail::AxisFunction& f = link.functions[i];
    axes.emplace_back(link.axes[i].x(), link.axes[i].y(), link.axes[i].z());
    if (f.coordinate < 0) {
      functions.push_back(new SimTK::Function::Constant(f.intercept, 0));
      arguments.emplace_back();
    } else {
      SimTK::Vector coefficients(2);
      coefficients[0] = f.slope;
      coefficients[1] = f.intercept;
      functions.push_back(new SimTK::Function::Linear(coefficients));
      const auto k = std::find(link.coordinates.begin(), link.coordinates.end(), f.coordinate) - link.coordinates.begin();
      arguments.push_back({static_cast<int>(k)});
    }
  }
  return SimTK::MobilizedBody::FunctionBased(parent, toSimTK(link.X_PF), body, toSimTK(link.X_BM),
                                             static_cast<int>(link.coordinates.size()), functions, arguments, axes)
      .getMobilizedBodyIndex();
}

}  // namespace

struct Skeleton::Impl {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::State state;

  detail::SkeletonDescription description;
  std::vector<std::string> coordinate_names;
  std::vector<std::string> body_names;
  std::vector<SimTK::MobilizedBodyIndex> coordinate_mobod;  ///< the mobilizer that owns each coordinate
  std::vector<int> coordinate_q;                            ///< its q index within that mobilizer
  std::vector<SimTK::MobilizedBodyIndex> body_mobod;
  Eigen::VectorXd q_rad;
  Eigen::VectorXd rest_q;
};

Skeleton Skeleton::fromUrdf(const std::string& urdf_path) {
  return build(detail::describeUrdf(detail::readUrdf(urdf_path)));
}

Skeleton Skeleton::fromOsim(const std::string& osim_path) {
  return build(detail::readOsim(osim_path));
}

Skeleton Skeleton::fromUrdfText(const std::string& text, const std::string& path) {
  return build(detail::describeUrdf(detail::parseUrdf(text, path)));
}

Skeleton Skeleton::fromOsimText(const std::string& text, const std::string& path) {
  return build(detail::parseOsim(text, path));
}

Skeleton Skeleton::fromFile(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".urdf") return fromUrdf(path);
  if (ext == ".osim") return fromOsim(path);
  throw ModelError("skeleton " + path + ": extension '" + ext +
                   "' is not a skeleton format (expected .urdf or .osim)");
}

Skeleton Skeleton::build(detail::SkeletonDescription d) {
  auto impl = std::make_unique<Impl>();
  for (const auto& c : d.coordinates) impl->coordinate_names.push_back(c.name);
  impl->coordinate_mobod.resize(d.coordinates.size());
  impl->coordinate_q.assign(d.coordinates.size(), 0);

  for (const detail::SkeletonBody& link : d.bodies) {
    const SimTK::Body::Rigid body = makeRigidBody(d, link);
    SimTK::MobilizedBody& parent =
        link.parent < 0 ? static_cast<SimTK::MobilizedBody&>(impl->matter.updGround())
                        : impl->matter.updMobilizedBody(impl->body_mobod[link.parent]);
    SimTK::MobilizedBodyIndex index;
    switch (link.joint_kind) {
      case detail::JointKind::kRoot:
        index = SimTK::MobilizedBody::Weld(parent, SimTK::Transform(), body, SimTK::Transform())
                    .getMobilizedBodyIndex();
        break;
      case detail::JointKind::kWeld:
        index = SimTK::MobilizedBody::Weld(parent, toSimTK(link.X_PF), body, toSimTK(link.X_BM))
                    .getMobilizedBodyIndex();
        break;
      case detail::JointKind::kPin: {
        // Inboard frame F·R_JA in the parent, outboard M·R_JA in the child, so
        // X_PB(q) = X_PF · R_JA · Rz(q) · R_JAᵀ · X_BMᵀ = X_PF · Rot(axis, q) · X_BMᵀ.
        const Eigen::Isometry3d X_JA = pinAxisFrame(link.pin_axis);
        index = SimTK::MobilizedBody::Pin(parent, toSimTK(link.X_PF * X_JA), body, toSimTK(link.X_BM * X_JA))
                    .getMobilizedBodyIndex();
        impl->coordinate_mobod[link.coordinates.at(0)] = index;
        impl->coordinate_q[link.coordinates.at(0)] = 0;
        break;
      }
      case detail::JointKind::kSpatial: {
        const int n = static_cast<int>(link.coordinates.size());
        if (n == 0) {  // every axis constant: a weld at the constant pose
          const Eigen::Isometry3d X_FM = detail::calcJointTransform(link, Eigen::VectorXd());
          index = SimTK::MobilizedBody::Weld(parent, toSimTK(link.X_PF * X_FM), body, toSimTK(link.X_BM))
                      .getMobilizedBodyIndex();
          break;
        }
        index = addFunctionBased(parent, body, link);
        for (int k = 0; k < n; ++k) {
          impl->coordinate_mobod[link.coordinates[k]] = index;
          impl->coordinate_q[link.coordinates[k]] = k;
        }
        break;
      }
    }
    impl->body_names.push_back(link.name);
    impl->body_mobod.push_back(index);
  }

  // The readers check mass properties, poses and axes; whatever Simbody still refuses is named
  // with the file instead of escaping as a SimTK exception.
  try {
    impl->system.realizeTopology();
  } catch (const std::exception& e) {
    std::string why = e.what();  // Simbody's text spans lines: one line for the error message
    std::replace(why.begin(), why.end(), '\n', ' ');
    throw ModelError(d.format + " " + d.path + ": Simbody cannot build the skeleton: " + why);
  }
  impl->state = impl->system.getDefaultState();
  impl->q_rad = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(d.coordinates.size()));
  for (std::size_t i = 0; i < d.coordinates.size(); ++i) impl->q_rad[static_cast<Eigen::Index>(i)] = d.coordinates[i].default_value;
  impl->rest_q = impl->q_rad;
  impl->description = std::move(d);
  return Skeleton(std::move(impl));
}

Skeleton::Skeleton(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) { setCoordinateValues(impl_->q_rad); }
Skeleton::Skeleton(Skeleton&&) noexcept = default;
Skeleton& Skeleton::operator=(Skeleton&&) noexcept = default;
Skeleton::~Skeleton() = default;

const std::string& Skeleton::getName() const { return impl_->description.name; }
const std::string& Skeleton::getModelPath() const { return impl_->description.path; }
const std::string& Skeleton::getUrdfPath() const { return impl_->description.path; }
const std::vector<std::string>& Skeleton::getCoordinateNames() const { return impl_->coordinate_names; }
const std::vector<CoordinateInfo>& Skeleton::getCoordinates() const { return impl_->description.coordinates; }

Eigen::VectorXd Skeleton::getDefaultCoordinateValues() const {
  const auto& c = impl_->description.coordinates;
  Eigen::VectorXd q(static_cast<Eigen::Index>(c.size()));
  for (std::size_t i = 0; i < c.size(); ++i) q[static_cast<Eigen::Index>(i)] = c[i].default_value;
  return q;
}

const Eigen::VectorXd& Skeleton::getRestCoordinateValues() const { return impl_->rest_q; }

void Skeleton::setRestCoordinateValues(const Eigen::VectorXd& q) {
  checkCoordinates(q, "setRestCoordinateValues");
  impl_->rest_q = q;
}

Eigen::VectorXd Skeleton::solveBodiesAtGround() const {
  return detail::solveBodiesAtGround(impl_->description, impl_->rest_q, 0.01, 1e-6);
}

void Skeleton::checkCoordinates(const Eigen::VectorXd& q, const char* caller) const {
  const Impl& m = *impl_;
  if (q.size() != static_cast<Eigen::Index>(m.coordinate_names.size()))
    throw std::invalid_argument("Skeleton '" + getName() + "': " + caller + " got " + std::to_string(q.size()) +
                                " values, expected " + std::to_string(m.coordinate_names.size()));
  for (Eigen::Index i = 0; i < q.size(); ++i)
    if (!std::isfinite(q[i]))
      throw std::invalid_argument("Skeleton '" + getName() + "': coordinate '" + m.coordinate_names[i] +
                                  "' set to a non-finite value");
}
const std::vector<std::string>& Skeleton::getBodyNames() const { return impl_->body_names; }

int Skeleton::findCoordinateIndex(const std::string& name) const {
  const auto& v = impl_->coordinate_names;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i] == name) return static_cast<int>(i);
  return -1;
}

int Skeleton::findBodyIndex(const std::string& name) const {
  const auto& v = impl_->body_names;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i] == name) return static_cast<int>(i);
  return -1;
}

void Skeleton::setCoordinateValues(const Eigen::VectorXd& q_rad) {
  Impl& m = *impl_;
  checkCoordinates(q_rad, "setCoordinateValues");
  for (Eigen::Index i = 0; i < q_rad.size(); ++i)
    m.matter.getMobilizedBody(m.coordinate_mobod[i]).setOneQ(m.state, m.coordinate_q[i], q_rad[i]);
  m.q_rad = q_rad;
  m.system.realize(m.state, SimTK::Stage::Position);
}

const Eigen::VectorXd& Skeleton::getCoordinateValues() const { return impl_->q_rad; }

Eigen::Isometry3d Skeleton::getBodyTransform(int body_index) const {
  const Impl& m = *impl_;
  if (body_index < 0 || body_index >= static_cast<int>(m.body_mobod.size()))
    throw std::out_of_range("Skeleton '" + getName() + "': body index " + std::to_string(body_index) +
                            " out of range [0, " + std::to_string(m.body_mobod.size()) + ")");
  return toEigen(m.matter.getMobilizedBody(m.body_mobod[body_index]).getBodyTransform(m.state));
}

const std::vector<BodyMesh>& Skeleton::getBodyMeshes(int body_index) const {
  const Impl& m = *impl_;
  if (body_index < 0 || body_index >= static_cast<int>(m.body_mobod.size()))
    throw std::out_of_range("Skeleton '" + getName() + "': body index " + std::to_string(body_index) +
                            " out of range [0, " + std::to_string(m.body_mobod.size()) + ")");
  return m.description.bodies[static_cast<std::size_t>(body_index)].meshes;
}

}  // namespace rbfmuscle
