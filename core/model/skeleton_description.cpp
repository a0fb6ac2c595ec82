// SPDX-License-Identifier: Apache-2.0
#include "model/skeleton_description.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "model/model_error.h"

namespace rbfmuscle::detail {
namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

double axisValue(const AxisFunction& f, const Eigen::VectorXd& q) {
  return f.coordinate < 0 ? f.intercept : f.slope * q[f.coordinate] + f.intercept;
}

/// Rotation vector (axis · angle, rad) of R.
Eigen::Vector3d rotationVector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

/// The rotation part of a joint as a function of the joint's own rotational unknowns x.
struct RotationChain {
  std::vector<Eigen::Vector3d> axes;  ///< applied in order, each in the frame the ones before produced
  std::vector<int> unknown;           ///< index into x, or −1 for a fixed angle
  std::vector<double> slope, intercept;

  Eigen::Matrix3d rotation(const Eigen::VectorXd& x) const {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    for (std::size_t i = 0; i < axes.size(); ++i) {
      const double angle = unknown[i] < 0 ? intercept[i] : slope[i] * x[unknown[i]] + intercept[i];
      R = R * Eigen::AngleAxisd(angle, axes[i]).toRotationMatrix();
    }
    return R;
  }
};

/// Unknowns x that bring chain.rotation(x) to R_target: damped Gauss–Newton (numerical
/// Jacobian) from starts x0 + {0, π/2, −π/2, π} per unknown; at most 100 iterations per start.
/// Returns the best x; `residual_rad` is the angle left.
Eigen::VectorXd solveRotation(const RotationChain& chain, const Eigen::Matrix3d& R_target, const Eigen::VectorXd& x0,
                              double& residual_rad) {
  const Eigen::Index n = x0.size();
  const auto residual = [&](const Eigen::VectorXd& x) {
    return rotationVector(chain.rotation(x).transpose() * R_target);
  };
  Eigen::VectorXd best = x0;
  residual_rad = residual(x0).norm();
  if (n == 0) return best;
  const double offsets[] = {0.0, kPi / 2, -kPi / 2, kPi};
  long starts = 1;
  for (Eigen::Index k = 0; k < n; ++k) starts *= 4;
  for (long s = 0; s < starts && residual_rad > 1e-13; ++s) {
    Eigen::VectorXd x = x0;
    long code = s;
    for (Eigen::Index k = 0; k < n; ++k, code /= 4) x[k] += offsets[code % 4];
    Eigen::Vector3d r = residual(x);
    double lambda = 1e-3;
    for (int iteration = 0; iteration < 100 && r.norm() > 1e-15; ++iteration) {
      Eigen::MatrixXd J(3, n);
      const double h = 1e-7;
      for (Eigen::Index k = 0; k < n; ++k) {
        Eigen::VectorXd xp = x, xm = x;
        xp[k] += h;
        xm[k] -= h;
        J.col(k) = (residual(xp) - residual(xm)) / (2 * h);
      }
      const Eigen::MatrixXd JtJ = J.transpose() * J;
      const Eigen::MatrixXd A = JtJ + lambda * Eigen::MatrixXd(JtJ.diagonal().asDiagonal()) +
                                1e-15 * Eigen::MatrixXd::Identity(n, n);
      const Eigen::VectorXd dx = A.ldlt().solve(-J.transpose() * r);
      const Eigen::Vector3d r_new = residual(x + dx);
      if (r_new.norm() < r.norm()) {
        x += dx;
        r = r_new;
        lambda = std::max(lambda / 10, 1e-12);
      } else {
        lambda *= 10;
        if (lambda > 1e8) break;
      }
    }
    if (r.norm() < residual_rad) {
      residual_rad = r.norm();
      best = x;
    }
  }
  return best;
}

}  // namespace

std::string findMassPropertiesProblem(double mass_kg, const Eigen::Matrix3d& I_C) {
  std::ostringstream why;
  if (!std::isfinite(mass_kg) || mass_kg < 0.0 || mass_kg > kMaxBodyMass_kg) {
    why << "mass " << mass_kg << " kg: expected a finite mass from 0 to " << kMaxBodyMass_kg << " kg";
    return why.str();
  }
  if (!I_C.allFinite() || !I_C.isApprox(I_C.transpose(), 0.0)) return "inertia: expected finite, symmetric values";
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I_C, Eigen::EigenvaluesOnly).eigenvalues();
  const double largest = moments.cwiseAbs().maxCoeff();
  if (largest == 0.0) return "";  // a massless point: no inertia at all
  // A moment of 0, or one equal to the sum of the other two (a rod, a flat plate), is a limit no
  // body reaches, and rounding as Simbody turns the inertia with its body leaves a diagonal
  // below 0 or a broken triangle inequality, which Simbody throws for at that pose: each must
  // clear these bounds by a margin far above rounding.
  const double margin = kMinInertiaMargin * largest;
  const double sum = moments.sum();
  for (int k = 0; k < 3; ++k)
    if (moments[k] < margin || moments[k] > kMaxBodyInertia_kgm2 || moments[k] > sum - moments[k] - margin) {
      why << "inertia about the mass centre has principal moments " << moments[0] << ", " << moments[1] << ", "
          << moments[2] << ": expected each above 0 and below the sum of the other two by at least "
          << kMinInertiaMargin << " of the largest, and at most " << kMaxBodyInertia_kgm2
          << " (no rigid body has other moments; a rod's zero moment or a flat plate's cannot be posed)";
      return why.str();
    }
  return "";
}

Eigen::Isometry3d calcJointTransform(const SkeletonBody& body, const Eigen::VectorXd& q) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  switch (body.joint_kind) {
    case JointKind::kRoot:
    case JointKind::kWeld:
      break;
    case JointKind::kPin:
      X.linear() = Eigen::AngleAxisd(q[body.coordinates.at(0)], body.pin_axis).toRotationMatrix();
      break;
    case JointKind::kSpatial: {
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      for (int i = 0; i < 3; ++i)
        R = R * Eigen::AngleAxisd(axisValue(body.functions[i], q), body.axes[i]).toRotationMatrix();
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (int i = 3; i < 6; ++i) p += axisValue(body.functions[i], q) * body.axes[i];
      X.linear() = R;
      X.translation() = p;
      break;
    }
  }
  return X;
}

Eigen::VectorXd solveBodiesAtGround(const SkeletonDescription& d, const Eigen::VectorXd& q_start,
                                    double tolerance_mm, double tolerance_rad) {
  Eigen::VectorXd q = q_start;
  for (const SkeletonBody& body : d.bodies) {
    if (body.joint_kind == JointKind::kRoot) continue;
    // X_PB = X_PF · X_FM · X_BMᵀ = identity when X_FM = X_PFᵀ · X_BM.
    const Eigen::Isometry3d target = body.X_PF.inverse() * body.X_BM;

    RotationChain chain;
    std::vector<int> rotation_coordinates;  // x[k] is q[rotation_coordinates[k]]
    Eigen::MatrixXd A(3, 0);                // translation: A · t = rhs over the translational unknowns
    Eigen::Vector3d rhs = target.translation();
    std::vector<int> translation_coordinates;
    const auto addRotation = [&](const Eigen::Vector3d& axis, const AxisFunction& f) {
      chain.axes.push_back(axis);
      chain.slope.push_back(f.slope);
      chain.intercept.push_back(f.intercept);
      if (f.coordinate < 0) {
        chain.unknown.push_back(-1);
      } else {
        chain.unknown.push_back(static_cast<int>(rotation_coordinates.size()));
        rotation_coordinates.push_back(f.coordinate);
      }
    };
    if (body.joint_kind == JointKind::kPin) {
      AxisFunction f;
      f.coordinate = body.coordinates.at(0);
      f.slope = 1.0;
      addRotation(body.pin_axis, f);
    } else if (body.joint_kind == JointKind::kSpatial) {
      for (int i = 0; i < 3; ++i) addRotation(body.axes[i], body.functions[i]);
      for (int i = 3; i < 6; ++i) {
        const AxisFunction& f = body.functions[i];
        rhs -= f.intercept * body.axes[i];
        if (f.coordinate >= 0) {
          A.conservativeResize(3, A.cols() + 1);
          A.col(A.cols() - 1) = f.slope * body.axes[i];
          translation_coordinates.push_back(f.coordinate);
        }
      }
    }

    Eigen::VectorXd x0(static_cast<Eigen::Index>(rotation_coordinates.size()));
    for (std::size_t k = 0; k < rotation_coordinates.size(); ++k) x0[k] = q[rotation_coordinates[k]];
    double rotation_left = 0.0;
    const Eigen::VectorXd x = solveRotation(chain, target.linear(), x0, rotation_left);
    for (std::size_t k = 0; k < rotation_coordinates.size(); ++k) q[rotation_coordinates[k]] = x[k];

    double translation_left = rhs.norm();
    if (A.cols() > 0) {
      const Eigen::VectorXd t = A.colPivHouseholderQr().solve(rhs);
      for (std::size_t k = 0; k < translation_coordinates.size(); ++k) q[translation_coordinates[k]] = t[k];
      translation_left = (A * t - rhs).norm();
    }
    if (!(rotation_left <= tolerance_rad) || !(translation_left <= tolerance_mm)) {
      std::ostringstream m;
      m << d.format << " " << d.path << ": rest pose with every body at ground: joint '" << body.joint_name
        << "' cannot put body '" << body.name << "' there: the closest pose leaves its frame "
        << translation_left << " mm and " << rotation_left * 180.0 / kPi << " deg away (tolerance "
        << tolerance_mm << " mm, " << tolerance_rad << " rad)";
      throw ModelError(m.str());
    }
  }
  return q;
}

}  // namespace rbfmuscle::detail
