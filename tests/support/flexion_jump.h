#pragma once
/// Issue 4's jump criterion for hip flexion, shared by the deformer's stability tests and the
/// main-job test (scripts/surface_jumps.py measures the same): a surface point may move between
/// frames by the femur's own move there plus 1 mm.
#include <Eigen/Core>

#include <cmath>

namespace rbfmuscle::test {

/// Hip joint centre and flexion axis (pelvis Z) in the CT frame (models/hip/landmarks/hip_frame.json).
inline const Eigen::Vector3d kHipCentre_CT_mm(143.225, 243.37, -432.499);
inline const Eigen::Vector3d kFlexionAxis_CT =
    Eigen::Vector3d(-0.9924778435393229, 0.11879490607095865, 0.029588855590025775).normalized();

/// The move allowed at p (mm) in a flexion step of `step_rad` about the axis through `hip_mm`:
/// the femur's own move there, 2 r sin(step/2) (r: distance from the axis), plus 1 mm.
inline double calcJumpAllowance_mm(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& hip_mm, double step_rad) {
  const Eigen::Vector3d u = p_mm - hip_mm;
  const double r_mm = (u - u.dot(kFlexionAxis_CT) * kFlexionAxis_CT).norm();
  return 2.0 * r_mm * std::sin(0.5 * step_rad) + 1.0;
}

}  // namespace rbfmuscle::test
