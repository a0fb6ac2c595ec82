// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to core/model: an OpenSim model file (.osim) read into the neutral skeleton
/// description (skeleton_description.h) that the Simbody builder reads, lengths converted from
/// the model's units (metres, or `<length_units>`) to mm once, here.
///
/// XML is read with tinyxml2, not SimTK::Xml (which comes with Simbody): every error must name
/// the XML line, and SimTK::Xml keeps no line numbers, while tinyxml2 does
/// (XMLElement::GetLineNum); the model XML of this project is read with tinyxml2 already.
///
/// Read (both layouts):
/// - OpenSim 3.x (Version < 40000, e.g. 30000): BodySet with each body's joint nested in its
///   `<Joint>` (parent_body, location_in_parent, orientation_in_parent, location, orientation;
///   orientations are body-fixed XYZ angles in rad), ground a Body named `ground`, geometry in
///   VisibleObject (GeometrySet/DisplayGeometry with transform and scale_factors, or the older
///   geometry_files), composed as OpenSim's own 3.x → 4.x conversion does: X_BG = X_outer · X_inner,
///   scale = scale_outer ∘ scale_inner.
/// - OpenSim 4.x: `<Ground>`, BodySet (attached_geometry Mesh; PhysicalOffsetFrames in a body's
///   components carrying meshes), JointSet with socket_parent_frame / socket_child_frame naming a
///   body, ground, or a PhysicalOffsetFrame of the joint's `<frames>` or of a body's components
///   (socket_parent path, translation, orientation; frames on frames up to 16 deep).
/// - Joints: CustomJoint (SpatialTransform of six TransformAxis: rotation1–3 then
///   translation1–3, each with at most one coordinate and a LinearFunction or Constant, also
///   inside a MultiplierFunction), PinJoint (rotation about the joint frames' Z) and WeldJoint.
/// - Coordinates: name, range and default_value (rad, or model length units for translational
///   ones, which become mm); a coordinate is rotational or translational by the axis it drives.
///   locked, clamped, prescribed and motion_type are not read: motions prescribe every coordinate.
/// - Bodies: mass, mass_center, inertia (3.x inertia_xx … inertia_yz, 4.x `<inertia>`), about the
///   mass centre; a body without positive mass gets kDefaultLinkMass_kg as in the URDF reader.
/// - Geometry files .vtp, .stl, .obj, .ply, looked for as written (backslashes read as '/'),
///   relative to the model's folder, then in its Geometry/ and geometry/ subfolders by file name.
///   Other geometry (spheres, cylinders, frames) is not a bone mesh and is skipped.
///
/// Refused with ModelError naming the file, the XML line and the element: a function other than
/// LinearFunction or Constant (SimmSpline, NaturalCubicSpline, GCVSpline, PiecewiseLinearFunction,
/// PolynomialFunction, …) or a MultiplierFunction around one (a non-linear coupling); a
/// coordinate driving two transform axes (coupled motion); a TransformAxis with two coordinates;
/// a coordinate that drives nothing; collinear axes; an enforced constraint (ConstraintSet); a
/// joint type other than CustomJoint, PinJoint, WeldJoint; a reversed joint; a body with no joint
/// or two, or not connected to ground; a frame that cannot be resolved; a missing geometry file.
#include <cstdint>
#include <string>

#include "model/skeleton_description.h"

namespace rbfmuscle::detail {

/// Reads an OpenSim model: bodies root (ground) first, each parent before its children.
/// @throws ModelError "OpenSim model PATH, line N: <Element name="…">: what was expected".
SkeletonDescription readOsim(const std::string& path);

/// Parses the text of an OpenSim model held in memory (what readOsim does after reading the
/// file); `path` names the file in errors, and geometry files are looked for beside it.
/// @throws ModelError as readOsim.
SkeletonDescription parseOsim(const std::string& text, const std::string& path);

/// Farthest a mass centre may lie from its body's origin (mm): 1000 m, as URDF origins.
inline constexpr double kMaxOsimOffset_mm = 1e6;

/// Largest OpenSim model file read (bytes): 64 MiB; full-body models are under 2 MB.
inline constexpr std::uintmax_t kMaxOsimFileBytes = 64ull << 20;

}  // namespace rbfmuscle::detail
