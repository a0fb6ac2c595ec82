// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Test-plugin component: reports a point fixed in a body, in ground.
///
/// XML element `<BodyOriginReporter name="...">`:
///   property  point_mm (Vector3, default 0 0 0): point P fixed in body B, p_BP (mm)
///   socket    socket_body (body): the body B
///   outputs   x_mm, y_mm, z_mm (double, mm): p_GP = X_GB · p_BP, position of P in ground
///   property  x_min_mm (double, default -1e9): the invariant it declares, x_mm ≥ x_min_mm, which
///             the host checks every frame (a higher value makes a run break it, for host tests)
#include "framework/component.h"

#include <Eigen/Core>

#include <limits>

namespace rbfmuscle::testplugin {

class BodyOriginReporter final : public Component {
 public:
  Property<Eigen::Vector3d> point_mm{this, "point_mm", Eigen::Vector3d::Zero(),
                                     "point P fixed in the body, p_BP (mm, body frame B)"};
  Property<double> x_min_mm{this, "x_min_mm", -1e9, "invariant: x of P in ground stays at least this (mm)"};
  BodySocket body{this, "body", "body B that carries the point"};
  Output x_mm{this, "x_mm", "mm", "x of P in ground G", [this] { return result_.p_GP_mm.x(); }};
  Output y_mm{this, "y_mm", "mm", "y of P in ground G", [this] { return result_.p_GP_mm.y(); }};
  Output z_mm{this, "z_mm", "mm", "z of P in ground G", [this] { return result_.p_GP_mm.z(); }};

  /// Declares the invariant x_mm ≥ x_min_mm.
  void initialize(const InitContext& context) override;
  /// p_GP = X_GB · p_BP.
  void update(const FrameState& state) override;

 private:
  struct Result {
    /// P in ground (mm); NaN until the first update.
    Eigen::Vector3d p_GP_mm = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  };
  Result result_;
};

}  // namespace rbfmuscle::testplugin
