#pragma once
/// @file
/// The RBFMuscle component: one muscle as a Gaussian RBF implicit surface that
/// follows the bones by curvature-preserving descent with its volume kept.
///
/// XML element `<RBFMuscle name="...">` (lengths in mm in the ground frame at
/// rest — the CT frame of the meshes — unless said otherwise):
///   mesh_file (string, required)          muscle mesh at rest, relative to the model file
///   surface_file (string, "")             cached fitted surface (.rbf): read when its mesh hash
///                                         matches; fitted and written when missing; an error when
///                                         it belongs to another mesh (never refitted silently)
///   centres (int, 1000)                   centre budget when a fit is needed
///   origin_landmarks_mm (string, "")      "x y z; x y z; …": centres within landmark_radius_mm
///                                         of one of these move rigidly with socket_origin_body
///   insertion_landmarks_mm (string, "")   the same for socket_insertion_body
///   landmark_radius_mm (double, 15)       attachment radius around each landmark
///   proximity_mm (double, 0)              also attach centres whose Gaussian support comes
///                                         within this distance of a bone's collision mesh at
///                                         rest (0: off); the nearest bone wins
///   quadrature_points (int, 4000)         points carrying the rest curvature κ₀
///   max_iterations (int, 50)              descent iteration cap per frame
///   cost_tolerance (double, 1e-5)         descent stops when the relative decrease is below
///   regularisation (double, 1e-2)         ρ: pull of each free centre towards its prediction
///   keep_volume (bool, true)              correct the offset b each frame to the rest volume
///   volume_tolerance (double, 1e-3)       |V/V_rest − 1| accepted
///   surface_cell_mm (double, 2)           grid cell of the surface written with --frames-mesh
///   socket_origin_body, socket_insertion_body: the bones
/// Outputs: volume_mm3, volume_ratio, curvature_cost, iterations (descent),
///   update_ms, descent_ms, attached_centres.
/// The muscle frame M is the ground frame shifted to the rest mesh's box centre.
#include <Eigen/Geometry>

#include <limits>
#include <memory>

#include "framework/component.h"

namespace rbfmuscle {

class MuscleDeformer;

class RBFMuscle final : public Component {
 public:
  Property<std::string> mesh_file{this, "mesh_file", "muscle mesh at rest (mm, ground frame), relative to the model file"};
  Property<std::string> surface_file{this, "surface_file", std::string(),
                                     "cached fitted surface (.rbf), relative to the model file; '' = fit every run"};
  Property<int> centres{this, "centres", 1000, "centre budget when fitting", PropertyRange{1, 100000}};
  Property<std::string> origin_landmarks_mm{this, "origin_landmarks_mm", std::string(),
                                            "'x y z; …' origin landmarks (mm, ground at rest)"};
  Property<std::string> insertion_landmarks_mm{this, "insertion_landmarks_mm", std::string(),
                                               "'x y z; …' insertion landmarks (mm, ground at rest)"};
  Property<double> landmark_radius_mm{this, "landmark_radius_mm", 15.0,
                                      "centres this close to a landmark attach (mm)", PropertyRange{0.1, 1000.0}};
  Property<double> proximity_mm{this, "proximity_mm", 0.0,
                                "attach centres whose support reaches this close to a bone (mm, 0 = off)",
                                PropertyRange{0.0, 100.0}};
  Property<int> quadrature_points{this, "quadrature_points", 4000, "quadrature points of the curvature cost",
                                  PropertyRange{8, 1000000}};
  Property<int> max_iterations{this, "max_iterations", 50, "descent iteration cap per frame", PropertyRange{1, 100000}};
  Property<double> cost_tolerance{this, "cost_tolerance", 1e-5, "relative cost decrease that stops the descent",
                                  PropertyRange{0.0, 1.0}};
  Property<double> regularisation{this, "regularisation", 1e-2, "ρ: pull of free centres to their prediction",
                                  PropertyRange{0.0, 1e6}};
  Property<bool> keep_volume{this, "keep_volume", true, "correct the offset b to keep the rest volume"};
  Property<double> volume_tolerance{this, "volume_tolerance", 1e-3, "accepted |V/V_rest − 1|",
                                    PropertyRange{1e-9, 1.0}};
  Property<double> surface_cell_mm{this, "surface_cell_mm", 2.0, "grid cell of per-frame surfaces (mm)",
                                   PropertyRange{0.05, 50.0}};
  BodySocket origin_body{this, "origin_body", "bone of the origin attachment"};
  BodySocket insertion_body{this, "insertion_body", "bone of the insertion attachment"};
  Output volume_mm3{this, "volume_mm3", "mm^3", "muscle volume {f > 0}", [this] { return result_.volume_mm3; }};
  Output volume_ratio{this, "volume_ratio", "1", "volume / rest volume", [this] { return result_.volume_ratio; }};
  Output curvature_cost{this, "curvature_cost", "1", "Σ w (κ − κ₀)² after the descent, normalised",
                        [this] { return result_.curvature_cost; }};
  Output iterations{this, "iterations", "1", "descent iterations this frame", [this] { return result_.iterations; }};
  Output update_ms{this, "update_ms", "ms", "wall time of this muscle's update", [this] { return result_.update_ms; }};
  Output descent_ms{this, "descent_ms", "ms", "wall time of the descent", [this] { return result_.descent_ms; }};
  Output attached_centres{this, "attached_centres", "1", "centres moving rigidly with a bone",
                          [this] { return result_.attached_centres; }};

  RBFMuscle();
  ~RBFMuscle() override;

  void initialize(const InitContext& context) override;
  void update(const FrameState& state) override;
  void appendFrameGeometry(std::vector<FrameGeometry>& geometry) const override;

 private:
  /// One frame's figures; NaN until the first update.
  struct Result {
    static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    double volume_mm3 = kNaN;
    double volume_ratio = kNaN;
    double curvature_cost = kNaN;
    double iterations = kNaN;
    double update_ms = kNaN;
    double descent_ms = kNaN;
    double attached_centres = kNaN;
  };

  Result result_;
  std::unique_ptr<MuscleDeformer> deformer_;
  Eigen::Vector3d frame_offset_mm_ = Eigen::Vector3d::Zero();  ///< origin of M in ground
  std::vector<Eigen::Isometry3d> X_GB_rest_;                    ///< origin, insertion bone poses at rest
  std::vector<Eigen::Isometry3d> bone_motion_M_;                ///< per frame, reused
};

}  // namespace rbfmuscle
