// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to core/model: one joint of an OpenSim model read into the skeleton body it moves:
/// its kind (CustomJoint, PinJoint, WeldJoint), the transform axes and their functions, and the
/// coordinates it adds to the skeleton. The bodies and frames a joint connects are found by the
/// model reader (osim_description.cpp) first; the formats read are listed in osim_description.h.
#include <tinyxml2.h>

#include <Eigen/Geometry>

#include <string>

#include "model/osim_xml.h"
#include "model/skeleton_description.h"

namespace rbfmuscle::detail {

/// A joint as the model reader found it: its element, the bodies it joins and its frames.
struct OsimJoint {
  const tinyxml2::XMLElement* element = nullptr;
  std::string name, type, parent, child;
  Eigen::Isometry3d X_PF = Eigen::Isometry3d::Identity();  ///< mm
  Eigen::Isometry3d X_BM = Eigen::Isometry3d::Identity();  ///< mm
};

/// Reads joint `j` into `out`, the body it moves (kind, frames, axes, functions and coordinate
/// indices), appending its coordinates to `d.coordinates`.
/// @throws ModelError through `xml` naming the element when the joint is not supported.
void readOsimJoint(const OsimXml& xml, const OsimJoint& j, SkeletonBody& out, SkeletonDescription& d);

}  // namespace rbfmuscle::detail
