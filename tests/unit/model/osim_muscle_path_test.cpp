// SPDX-License-Identifier: Apache-2.0
// Muscle paths of OpenSim models: the subject's iliacus (3.x layout) against the file's own
// numbers, a 4.x path with a conditional point and a wrap, and the paths the reader refuses.
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <cmath>
#include <sstream>
#include <string>

#include "model/osim_muscle_path.h"
#include "model/skeleton.h"
#include "model_test_support.h"

namespace rbfmuscle {
namespace {

using test::expectModelError;

const std::string kOsim = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip/osim/LHDL_hip_r.osim";
const std::string kV4 = std::string(RBFMUSCLE_SOURCE_DIR) + "/tests/unit/model/data/osim/three_bodies_v4.osim";

/// The iliacus's path points straight from the XML (tinyxml2 here, not the reader): body, location (m).
std::vector<std::pair<std::string, Eigen::Vector3d>> readIliacusFromFile() {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.LoadFile(kOsim.c_str()), tinyxml2::XML_SUCCESS);
  std::vector<std::pair<std::string, Eigen::Vector3d>> out;
  const tinyxml2::XMLElement* forces = doc.RootElement()->FirstChildElement("Model")->FirstChildElement("ForceSet");
  for (const auto* m = forces->FirstChildElement("objects")->FirstChildElement(); m; m = m->NextSiblingElement()) {
    if (std::string(m->Attribute("name")) != "iliacus_r") continue;
    const auto* points = m->FirstChildElement("GeometryPath")->FirstChildElement("PathPointSet")->FirstChildElement("objects");
    for (const auto* p = points->FirstChildElement(); p; p = p->NextSiblingElement()) {
      std::istringstream in(p->FirstChildElement("location")->GetText());
      Eigen::Vector3d v;
      in >> v.x() >> v.y() >> v.z();
      out.emplace_back(p->FirstChildElement("body")->GetText(), v);
    }
  }
  return out;
}

TEST(OsimMusclePath, SubjectIliacusIsTheFilesPointsInMillimetres) {
  const Skeleton skeleton = Skeleton::fromOsim(kOsim);
  const MusclePath path = readOsimMusclePath(kOsim, "iliacus_r", skeleton);
  const auto expected = readIliacusFromFile();
  ASSERT_EQ(path.points.size(), expected.size());
  ASSERT_EQ(path.points.size(), 5u);
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(skeleton.getBodyNames()[static_cast<size_t>(path.points[i].body)], expected[i].first) << i;
    EXPECT_LT((path.points[i].location_B_mm - 1000.0 * expected[i].second).norm(), 1e-9) << i;
  }
  // The third point is on the path while hip flexion is within [-3.14159, 0.942478] rad.
  EXPECT_EQ(path.points[2].coordinate, skeleton.findCoordinateIndex("hip_flexion_r"));
  EXPECT_DOUBLE_EQ(path.points[2].active_min, -3.14159);
  EXPECT_DOUBLE_EQ(path.points[2].active_max, 0.942478);
  for (size_t i : {0u, 1u, 3u, 4u}) EXPECT_EQ(path.points[i].coordinate, -1) << i;
  EXPECT_TRUE(path.notes.empty());
}

TEST(OsimMusclePath, V4SocketsConditionalRangeInMillimetresAndWrapNoted) {
  const Skeleton skeleton = Skeleton::fromOsim(kV4);
  const MusclePath path = readOsimMusclePath(kV4, "vasti", skeleton);
  ASSERT_EQ(path.points.size(), 3u);
  EXPECT_EQ(path.points[0].body, skeleton.findBodyIndex("thigh"));
  EXPECT_EQ(path.points[2].body, skeleton.findBodyIndex("shank"));
  EXPECT_TRUE(path.points[1].location_B_mm.isApprox(Eigen::Vector3d(30, -350, 10), 1e-12));
  // knee_slide is translational: its range 0–0.01 m becomes 0–10 mm.
  EXPECT_EQ(path.points[1].coordinate, skeleton.findCoordinateIndex("knee_slide"));
  EXPECT_DOUBLE_EQ(path.points[1].active_min, 0.0);
  EXPECT_DOUBLE_EQ(path.points[1].active_max, 10.0);
  ASSERT_EQ(path.notes.size(), 1u);
  EXPECT_NE(path.notes[0].find("knee_cylinder"), std::string::npos);
}

TEST(OsimMusclePath, RefusedPathsNameTheElementAndLine) {
  const Skeleton skeleton = Skeleton::fromOsim(kV4);
  expectModelError([&] { readOsimMusclePath(kV4, "sliding", skeleton); },
                   {kV4 + ", line 149: <MovingPathPoint name=\"s2\">: path points of type MovingPathPoint are not "
                          "supported"});
  expectModelError([&] { readOsimMusclePath(kV4, "on_offset_frame", skeleton); },
                   {kV4 + ", line 158: <PathPoint name=\"o1\">: frame 'pelvis_offset' is not a body of the skeleton"});
  expectModelError([&] { readOsimMusclePath(kV4, "one_point", skeleton); },
                   {kV4 + ", line 164: <PathActuator name=\"one_point\">: its path has 1 points; expected at least 2"});
  expectModelError([&] { readOsimMusclePath(kV4, "vastus", skeleton); },
                   {kV4 + ": no muscle 'vastus'", "the model has: vasti, sliding, on_offset_frame, one_point"});
  // Points are in the model's body frames: a skeleton from another file is refused.
  const Skeleton other = Skeleton::fromOsim(kOsim);
  expectModelError([&] { readOsimMusclePath(kV4, "vasti", other); },
                   {"muscle 'vasti'", "the skeleton is read from " + kOsim});
}

TEST(OsimMuscleReference, ParsesOnlyOsimFileReferences) {
  EXPECT_FALSE(parseOsimMuscleReference("areas.json: A, B"));
  EXPECT_FALSE(parseOsimMuscleReference("1 2 3; 4 5 6"));
  const auto reference = parseOsimMuscleReference(" osim/Model.OSIM : glut_max1_r,glut_max2_r ");
  ASSERT_TRUE(reference);
  EXPECT_EQ(reference->file, "osim/Model.OSIM");
  EXPECT_EQ(reference->muscles, (std::vector<std::string>{"glut_max1_r", "glut_max2_r"}));
  expectModelError([] { parseOsimMuscleReference("m.osim: a,,b"); }, {"an empty muscle name"});
  expectModelError([] { parseOsimMuscleReference("m.osim: a,"); }, {"stray ','"});
  expectModelError([] { parseOsimMuscleReference("m.osim:"); }, {"no muscle name after ':'"});
}

}  // namespace
}  // namespace rbfmuscle
