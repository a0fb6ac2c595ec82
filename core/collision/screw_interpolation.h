#pragma once
/// @file
/// Interpolation between two rigid poses along the screw motion joining them, for
/// sub-stepping a frame (contact_resolver.h).
#include <Eigen/Geometry>

namespace rbfmuscle {

/// The pose a fraction s ∈ [0, 1] of the way from X_a to X_b along the screw motion
/// D = X_b X_a⁻¹ (Chasles): D is a rotation by θ about an axis u through a point c plus a
/// slide d·u along it; D(s) rotates by sθ about the same axis and slides by s·d, and the
/// result is D(s) X_a. So a rotation about a fixed point (a hip centre) is interpolated
/// exactly along its arc, not along the chord. For θ < 1e-12 rad the translation is
/// interpolated linearly. s = 0 gives X_a and s = 1 gives X_b (up to rounding).
Eigen::Isometry3d interpolateScrew(const Eigen::Isometry3d& X_a, const Eigen::Isometry3d& X_b, double s);

}  // namespace rbfmuscle
