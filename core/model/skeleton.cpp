#include "model/skeleton.h"

#include <Simbody.h>

#include <cmath>
#include <stdexcept>

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

}  // namespace

struct Skeleton::Impl {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::State state;

  std::string name;
  std::string urdf_path;
  std::vector<std::string> coordinate_names;
  std::vector<std::string> body_names;
  std::vector<SimTK::MobilizedBodyIndex> coordinate_mobod;  ///< the pin that owns each coordinate
  std::vector<SimTK::MobilizedBodyIndex> body_mobod;
  std::vector<std::vector<BodyMesh>> body_meshes;
  Eigen::VectorXd q_rad;
};

Skeleton Skeleton::fromUrdf(const std::string& urdf_path) {
  const detail::UrdfDescription d = detail::readUrdf(urdf_path);
  auto impl = std::make_unique<Impl>();
  impl->name = d.name;
  impl->urdf_path = urdf_path;

  for (const detail::UrdfLink& link : d.links) {
    SimTK::Body::Rigid body;
    try {
      SimTK::Mat33 I;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) I(i, j) = link.inertia_B_kgmm2(i, j);
      const Eigen::Vector3d& c = link.com_B_mm;
      body = SimTK::Body::Rigid(SimTK::MassProperties(
          link.mass_kg, SimTK::Vec3(c.x(), c.y(), c.z()), SimTK::Inertia(I)));
    } catch (const std::exception& e) {
      throw ModelError("URDF " + urdf_path + ": link '" + link.name +
                       "' has invalid mass properties (mass must be positive, inertia a valid "
                       "symmetric inertia matrix): " + e.what());
    }

    SimTK::MobilizedBody& parent =
        link.parent < 0 ? static_cast<SimTK::MobilizedBody&>(impl->matter.updGround())
                        : impl->matter.updMobilizedBody(impl->body_mobod[link.parent]);
    SimTK::MobilizedBodyIndex index;
    switch (link.joint_kind) {
      case detail::UrdfJointKind::kRoot:
        index = SimTK::MobilizedBody::Weld(parent, SimTK::Transform(), body, SimTK::Transform())
                    .getMobilizedBodyIndex();
        break;
      case detail::UrdfJointKind::kFixed:
        index = SimTK::MobilizedBody::Weld(parent, toSimTK(link.X_PJ), body, SimTK::Transform())
                    .getMobilizedBodyIndex();
        break;
      case detail::UrdfJointKind::kRevolute: {
        // Inboard frame F = J·R_JA in the parent, outboard M = R_JA in the child, so
        // X_PB(q) = X_PJ · R_JA · Rz(q) · R_JAᵀ = X_PJ · Rot(axis_J, q).
        const Eigen::Isometry3d X_JA = pinAxisFrame(link.axis_J);
        index = SimTK::MobilizedBody::Pin(parent, toSimTK(link.X_PJ * X_JA), body, toSimTK(X_JA))
                    .getMobilizedBodyIndex();
        impl->coordinate_names.push_back(link.joint_name);
        impl->coordinate_mobod.push_back(index);
        break;
      }
    }
    impl->body_names.push_back(link.name);
    impl->body_mobod.push_back(index);
    impl->body_meshes.push_back(link.meshes);
  }

  impl->system.realizeTopology();
  impl->state = impl->system.getDefaultState();
  impl->q_rad = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(impl->coordinate_names.size()));
  Skeleton skeleton(std::move(impl));
  skeleton.setCoordinateValues(skeleton.impl_->q_rad);
  return skeleton;
}

Skeleton::Skeleton(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Skeleton::Skeleton(Skeleton&&) noexcept = default;
Skeleton& Skeleton::operator=(Skeleton&&) noexcept = default;
Skeleton::~Skeleton() = default;

const std::string& Skeleton::getName() const { return impl_->name; }
const std::string& Skeleton::getUrdfPath() const { return impl_->urdf_path; }
const std::vector<std::string>& Skeleton::getCoordinateNames() const { return impl_->coordinate_names; }
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
  if (q_rad.size() != static_cast<Eigen::Index>(m.coordinate_names.size()))
    throw std::invalid_argument("Skeleton '" + m.name + "': setCoordinateValues got " +
                                std::to_string(q_rad.size()) + " values, expected " +
                                std::to_string(m.coordinate_names.size()));
  for (Eigen::Index i = 0; i < q_rad.size(); ++i) {
    if (!std::isfinite(q_rad[i]))
      throw std::invalid_argument("Skeleton '" + m.name + "': coordinate '" +
                                  m.coordinate_names[i] + "' set to a non-finite value");
    m.matter.getMobilizedBody(m.coordinate_mobod[i]).setOneQ(m.state, 0, q_rad[i]);
  }
  m.q_rad = q_rad;
  m.system.realize(m.state, SimTK::Stage::Position);
}

const Eigen::VectorXd& Skeleton::getCoordinateValues() const { return impl_->q_rad; }

Eigen::Isometry3d Skeleton::getBodyTransform(int body_index) const {
  const Impl& m = *impl_;
  if (body_index < 0 || body_index >= static_cast<int>(m.body_mobod.size()))
    throw std::out_of_range("Skeleton '" + m.name + "': body index " + std::to_string(body_index) +
                            " out of range [0, " + std::to_string(m.body_mobod.size()) + ")");
  return toEigen(m.matter.getMobilizedBody(m.body_mobod[body_index]).getBodyTransform(m.state));
}

const std::vector<BodyMesh>& Skeleton::getBodyMeshes(int body_index) const {
  const Impl& m = *impl_;
  if (body_index < 0 || body_index >= static_cast<int>(m.body_meshes.size()))
    throw std::out_of_range("Skeleton '" + m.name + "': body index " + std::to_string(body_index) +
                            " out of range [0, " + std::to_string(m.body_meshes.size()) + ")");
  return m.body_meshes[body_index];
}

}  // namespace rbfmuscle
