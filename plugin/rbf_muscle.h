// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The RBFMuscle component: one muscle as a Gaussian RBF surface whose kernels deform with the
/// tissue between its bones, kept out of the bones, with its volume and its fibres.
///
/// XML `<RBFMuscle name="...">` with the properties below (lengths in mm in the ground frame
/// at rest, the frame of the meshes), the stage settings `<fibres>`, `<volume>` and `<descent>`
/// (stage_settings.h), sockets `origin_body` and `insertion_body`, and outputs
/// generated from the frame pipeline's stage reports (core/pipeline/muscle_pipeline.h; listed
/// by `rbfmuscle info RBFMuscle`), with the invariants it promises on them every frame: volume
/// within the volume step's tolerance, finite positive volume and fibre lengths, and a tracked
/// surface (when there is one) no deeper in a bone than the surface's tolerance. The component
/// only wires: it turns properties into a
/// MuscleDefinition, hands each frame's bone poses to the pipeline, and reads its reports.
/// The muscle frame M is the ground frame shifted to the rest mesh's box centre.
#include "framework/component.h"
#include "stage_settings.h"

#include <Eigen/Geometry>

#include <functional>
#include <limits>
#include <memory>
#include <vector>

namespace rbfmuscle {

class MomentArms;
class MusclePipeline;
struct MuscleDefinition;
struct PipelineSettings;
class Skeleton;
struct ViaPointPath;

class RBFMuscle final : public Component {
 public:
  Property<std::string> mesh_file{this, "mesh_file", "muscle mesh at rest (mm, ground frame), relative to the model file"};
  Property<std::string> surface_file{this, "surface_file", std::string(),
                                     "fitted surface (.rbf) cached beside the model: read when it belongs to "
                                     "mesh_file, fitted and written when missing; '' = fit every run"};
  Property<int> centres{this, "centres", 1000, "Gaussian kernels of a fit", PropertyRange{1, 100000}};
  Property<std::string> origin_area{this, "origin_area",
                                    "origin attachment area on the origin body: 'FILE: CLOUD, …' (landmark clouds "
                                    "of a JSON file, relative to the model file), 'FILE.osim: MUSCLE, …' (their first "
                                    "path points in the skeleton's OpenSim model) or 'x y z; …' (mm, ground at rest)"};
  Property<std::string> insertion_area{this, "insertion_area",
                                       "insertion attachment area, as origin_area (from an OpenSim model: the "
                                       "muscles' last path points)"};
  Property<double> attachment_radius_mm{this, "attachment_radius_mm", 10.0,
                                        "kernels centred within this distance of an area point move rigidly with its "
                                        "bone (mm)",
                                        PropertyRange{0.1, 1000.0}};
  Property<std::string> line_of_action{this, "line_of_action", std::string(),
                                       "path to compare with: 'x y z @ BODY; …' via points, each fixed to the body "
                                       "named (mm, ground at rest); 'x y z; …' puts the first point on the origin "
                                       "body, the last on the insertion body, and the others on the origin body up to "
                                       "half the path's length, else on the insertion body; 'FILE.osim: MUSCLE' (a "
                                       "muscle of the OpenSim model the skeleton is read from); '' = the straight "
                                       "line between the areas' means"};
  Property<std::string> blend{this, "blend", "joint_angle",
                              "how the tissue between the bones takes their motions: 'distance' (weights by "
                              "inverse squared distance to each bone's attached kernels) or 'joint_angle' (by angle "
                              "about the centre of the joint between the two bodies, found from the skeleton: no fold "
                              "while the joint turns less than about 0.8 of the angle between the areas seen from it, "
                              "printed at start)"};
  Property<bool> lift_off{this, "lift_off", true,
                          "a shortened muscle lifts off its joint as a taut string lifts off a drum, each fibre "
                          "held where it leaves the origin body's bones at rest (blend 'joint_angle' and fibres only; "
                          "false: the tissue keeps its distance from the joint)"};
  Property<bool> contacts{this, "contacts", true,
                          "keep the muscle out of every body with a mesh (its collision meshes, else its visual ones; "
                          "false: bones are ignored)"};
  Property<std::string> moment_arms{this, "moment_arms", std::string(),
                                    "coordinates whose moment arms −∂l/∂q are reported (outputs moment_arm_<coordinate>_mm, "
                                    "the mean over fibres, fibre_moment_arm_<coordinate>_mm, each fibre's, and "
                                    "line_of_action_moment_arm_<coordinate>_mm): 'all' or names 'a, b'; '' = none. "
                                    "Each coordinate re-runs the frame twice (central difference)"};
  Property<double> check_pieces_cell_mm{this, "check_pieces_cell_mm", 0.0,
                                        "a check for tests and tools: count the pieces of the muscle outside the bones "
                                        "every frame on a grid of this cell (outputs pieces, stray_volume_mm3 and "
                                        "stray_centre_mm, and the invariant pieces = 1), the grid refined 4× around "
                                        "stray pieces; a field "
                                        "evaluation over the muscle's whole box, about 0.1–0.2 s a frame for each hip "
                                        "muscle at 2 mm; 0 = off",
                                        PropertyRange{0.0, 100.0}};
  FibreSubcomponent fibre_settings{this};
  VolumeSubcomponent volume_settings{this};
  DescentSubcomponent descent_settings{this};
  BodySocket origin_body{this, "origin_body", "bone of the origin attachment"};
  BodySocket insertion_body{this, "insertion_body", "bone of the insertion attachment"};

  RBFMuscle();
  ~RBFMuscle() override;

  void initialize(const InitContext& context) override;
  void update(const FrameState& state) override;
  void appendFrameGeometry(std::vector<FrameGeometry>& geometry) const override;

 private:
  /// The promises checked by the run loop after every frame (invariant.h).
  void declareInvariants(const PipelineSettings& settings);
  /// Reads an area property (rest, M; 3×K). `last`: an OpenSim muscle's insertion, else its origin.
  Eigen::Matrix3Xd readArea_M(const Property<std::string>& spec, const InitContext& context, bool last) const;
  /// Runs the pipeline and the line of action at body poses X_GB(body) and coordinates q.
  void runFrame(const std::function<Eigen::Isometry3d(int)>& X_GB, const Eigen::VectorXd& q, bool want_surface);
  /// The moment-arm probe and its outputs for the coordinates `moment_arms` names.
  void makeMomentArmOutputs(const Skeleton& skeleton);
  /// The centre (M, mm) of the joint between the origin and insertion bodies, for blend
  /// 'joint_angle'. @throws FrameworkError when the bodies have no joint centre.
  Eigen::Vector3d findJointCentre_M(const Skeleton& skeleton, const MuscleDefinition& muscle) const;
  /// Sets line_of_action_ and path_bodies_ from the property (default: the areas' means).
  void makeLineOfAction(const InitContext& context, const Eigen::Matrix3Xd& origin_area_M,
                        const Eigen::Matrix3Xd& insertion_area_M);

  std::vector<std::unique_ptr<Output>> report_outputs_;  ///< one per pipeline report field
  std::vector<double> report_values_;                    ///< the last frame's reports
  Output attached_kernels_output_{this, "attached_kernels", "1", "kernels moving rigidly with a bone",
                                  [this] { return attached_kernels_; }};
  Output line_of_action_output_{this, "line_of_action_length_mm", "mm",
                                "length of the via-point (or straight) line of action, for comparison",
                                [this] { return line_of_action_length_mm_; }};
  VectorOutput fibre_lengths_output_;
  Output pieces_output_{this, "pieces", "1", "pieces of the muscle outside the bones (check_pieces_cell_mm; NaN when off)",
                        [this] { return pieces_; }};
  Output stray_volume_output_{this, "stray_volume_mm3", "mm^3",
                              "volume of every piece but the largest (check_pieces_cell_mm; NaN when off)",
                              [this] { return stray_volume_mm3_; }};
  VectorOutput stray_centre_output_{this, "stray_centre_mm", "mm",
                                    "x, y, z (ground) of the mean of the second largest piece: the part that came "
                                    "off (check_pieces_cell_mm; NaN when off or in one piece)",
                                    [this]() -> const Eigen::VectorXd& { return stray_centre_G_mm_; }};

  std::unique_ptr<MusclePipeline> pipeline_;
  std::unique_ptr<MomentArms> moment_arms_;                   ///< null without moment_arms
  std::vector<std::unique_ptr<AbstractOutput>> moment_arm_outputs_;
  std::vector<double> fibre_moment_arm_mean_mm_, line_of_action_moment_arm_mm_;  ///< per probed coordinate
  std::vector<Eigen::VectorXd> fibre_moment_arms_mm_;                           ///< per probed coordinate
  std::unique_ptr<ViaPointPath> line_of_action_;
  Eigen::Vector3d frame_offset_mm_ = Eigen::Vector3d::Zero();  ///< origin of M in ground
  std::vector<int> bone_bodies_;                               ///< origin, insertion
  std::vector<Eigen::Isometry3d> X_GB_rest_;                   ///< their poses at rest
  std::vector<Eigen::Isometry3d> X_GB_path_rest_;              ///< path bodies' poses at rest
  std::vector<int> contact_bodies_;                            ///< skeleton body of each contact bone
  std::vector<int> path_bodies_;                               ///< skeleton body of each bone of the line of action
  std::vector<Eigen::Isometry3d> bone_motion_M_, path_motion_M_, X_MB_;  ///< per frame, reused
  double attached_kernels_ = 0.0;
  double line_of_action_length_mm_ = 0.0;
  double pieces_ = std::numeric_limits<double>::quiet_NaN();
  double stray_volume_mm3_ = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd stray_centre_G_mm_ = Eigen::VectorXd::Constant(3, std::numeric_limits<double>::quiet_NaN());
  Eigen::VectorXd no_fibres_;
};

}  // namespace rbfmuscle
