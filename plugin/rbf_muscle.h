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
///   supporting_bodies (string, "none")   "origin", "insertion", "both" or "none": the rest
///                                         surface of these bodies counts as attachment in the
///                                         blend weights of the prediction (attachment.h), so muscle
///                                         lying on the bone follows it
///   support_radius_mm (double, 0)         only the part of a supporting body's surface within
///                                         this distance of its attachment (landmarks, else attached
///                                         centres) counts (0: all of it). The hip scenes: the iliacus
///                                         with "origin" and 80 mm, the pelvis of the iliac fossa, so
///                                         the proxy beside the insertion does not hold the insertion
///                                         back (models/hip/README.md, Contacts)
///   quadrature_points (int, 4000)         points carrying the rest curvature κ₀
///   max_iterations (int, 50)              descent iteration cap per frame
///   cost_tolerance (double, 1e-5)         descent stops when the relative decrease is below
///   regularisation (double, 1e-2)         ρ: pull of each free centre towards its prediction
///   keep_volume (bool, true)              scale the free centres' weights each frame to the rest volume
///   volume_tolerance (double, 1e-3)       |V/V_rest − 1| accepted
///   neck_level (double, 0.2)              the island guard raises a thinning neck below this f
///                                         (field unit; 0 = off; core/dynamics/topology_guard.h)
///   crumb_join_level (double, 0.05)       a crumb of the surface beside the body across a shallow
///                                         dip is joined with its gap raised to this f, when that is
///                                         a smaller change than removing it (0 = always removed)
///   surface_cell_mm (double, 2)           grid cell of the surface written with --frames-mesh
///   fibres (int, 100)                     N fibres from origin to insertion through the volume
///                                         (core/fibres/fibre_generator.h; 0 = none); their ends
///                                         are spread over the interior within 10 mm (grown as
///                                         needed) of the origin / insertion landmarks, or of the
///                                         attached centres when no landmarks are given
///   fibre_segments (int, 15)              S segments per fibre
///   line_of_action_mm (string, "")        "x y z; …" via-point path (≥ 2 points, first on the
///                                         origin body, last on the insertion body, each
///                                         intermediate point on the body whose mesh is nearest at
///                                         rest, by arc length if a body has no mesh); "" = the
///                                         straight line from the mean origin landmark to the mean
///                                         insertion landmark (mean attached centres without landmarks)
///   contact_probes (int, 2000)            points on the surface f = 0 tested against the bones
///                                         (0: no contact handling at all); bones = every
///                                         skeleton body with a mesh (collision meshes, else visual)
///   contact_response (bool, false)        push free centres out of the bones, with sub-steps
///                                         against tunnelling (false: measure only); on in the hip
///                                         scenes. Its pushes need attachments that hold the muscle
///                                         near its bones: the iliacus without the support above
///                                         steps its fibre lengths by up to 2.2 % between 1° frames
///   contact_tolerance_mm (double, 0.5)    accepted penetration beyond the rest overlap
///   contact_max_iterations (int, 10)      cap on response iterations per (sub-)step
///   contact_max_reseats (int, 0)          cap on probes re-seated per (sub-)step where a bone
///                                         vertex is inside the muscle, more than the tolerance
///                                         deep, with no probe near (0: measured only, output
///                                         max_penetration_watched_mm; contact_resolver.h)
///   max_substeps (int, 8)                 cap on sub-steps per frame of the tunnelling guard
///   max_surface_step_mm (double, 0)       no surface point may end further from the previous frame's
///                                         surface than the bones move there plus this (mm; 0 = off;
///                                         0.5 in the hip scenes, the gluteus only in flexion): the
///                                         frame's correction is taken back part of the way and
///                                         points still beyond are pulled back locally
///                                         (core/dynamics/surface_step_limiter.h; outputs
///                                         step_excess_mm, step_scale, step_excess_left_mm). The
///                                         contact response comes after it and is not limited;
///                                         its push leaves the probes it moves 0.1 mm inside
///                                         contact_tolerance_mm, a push about the bone's advance
///   Contacts (core/collision/contact_resolver.h): each probe may stay as deep inside a bone as
///   it was at rest (documented rest overlap: the pelvis proxy overlaps the iliacus by up to
///   8 mm), only the excess counts and is resolved; a frame in which a bone point near the muscle
///   moves through it (along its normal) by more than half the local thickness is split into
///   sub-steps (bone poses interpolated along their screw motion, the deformer and the contacts
///   run per sub-step;
///   bone walls are taken as thicker than the muscle, ContactBone::thickness_mm = ∞).
///   Probes: contact_probes vertices of the rest surface (surface_cell_mm grid), carried by the
///   same dual-quaternion blend as the quadrature points and projected onto f = 0.
///   socket_origin_body, socket_insertion_body: the bones
/// Outputs: volume_mm3, volume_ratio, volume_correction (δ, volume_keeper.h), curvature_cost, iterations (descent),
///   update_ms, and of it predict_ms, descent_ms, volume_ms, guard_ms (summed over sub-steps);
///   islands_removed, islands_left (topology guard, core/dynamics/topology_guard.h); step_excess_mm,
///   step_scale, step_excess_left_mm (step limit, core/dynamics/surface_step_limiter.h); attached_centres;
///   fiber_length_mm (vector, one per fibre, columns fiber_length_mm_i), fiber_length_mean_mm,
///   fiber_length_min_mm, fiber_length_max_mm, fiber_length_normalised (mean / rest mean),
///   fiber_projections (fibre points, ends included, pushed back inside this frame; core/fibres/fibre_tracker.h),
///   fiber_end_offset_max_mm (largest move of a fibre end off its bone-rigid place, < 0.5 mm),
///   fiber_points_outside (fibre points still with f ≤ 0 after the projection; 0 when all are inside),
///   line_of_action_length_mm (the path of line_of_action_mm, or the straight line);
///   max_penetration_mm (largest probe depth inside a bone beyond its rest overlap after the
///   response, max over sub-steps), max_penetration_free_mm (the same over probes where the
///   surface is made mostly by free centres, i.e. not on attachment surface),
///   max_penetration_before_mm (the same before the response),
///   contacts (probes found beyond their rest overlap, max over sub-steps), probes_off_surface
///   (at the first measurement of each sub-step: deepest probes that stayed off the surface after
///   a second projection and were left out of the maxima, summed over sub-steps),
///   max_penetration_watched_mm (deepest muscle point below a bone vertex, before the response,
///   rest overlap left out, max over sub-steps: an independent check of the probes), probes_reseated
///   (probes moved to uncovered bone vertices inside the muscle, summed over sub-steps), substeps,
///   contact_iterations (response iterations, summed), collision_ms (probe carrying, queries and
///   response, all sub-steps; NaN without contact_probes).
/// Frame geometry (--frames-mesh): NAME (surface) and NAME_fibres (fibre polylines, ground, mm).
/// The muscle frame M is the ground frame shifted to the rest mesh's box centre.
#include <Eigen/Geometry>

#include <limits>
#include <memory>

#include "collision/contact_resolver.h"
#include "dynamics/surface_step_limiter.h"
#include "dynamics/topology_guard.h"
#include "framework/component.h"

namespace rbfmuscle {

class MuscleDeformer;
class FibreTracker;
class GaussianField;
class Skeleton;
struct Attachments;
struct ViaPointPath;

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
  Property<std::string> supporting_bodies{this, "supporting_bodies", "none",
                                          "bodies whose rest surface counts as attachment in the blend: "
                                          "origin, insertion, both or none"};
  Property<double> support_radius_mm{this, "support_radius_mm", 0.0,
                                     "a supporting body's surface counts within this distance of its landmarks "
                                     "(mm, 0 = all of it)",
                                     PropertyRange{0.0, 10000.0}};
  Property<int> quadrature_points{this, "quadrature_points", 4000, "quadrature points of the curvature cost",
                                  PropertyRange{8, 1000000}};
  Property<int> max_iterations{this, "max_iterations", 50, "descent iteration cap per frame", PropertyRange{1, 100000}};
  Property<double> cost_tolerance{this, "cost_tolerance", 1e-5, "relative cost decrease that stops the descent",
                                  PropertyRange{0.0, 1.0}};
  Property<double> regularisation{this, "regularisation", 1e-2, "ρ: pull of free centres to their prediction",
                                  PropertyRange{0.0, 1e6}};
  Property<bool> keep_volume{this, "keep_volume", true, "keep the rest volume through the free centres' weights"};
  Property<double> volume_tolerance{this, "volume_tolerance", 1e-3, "accepted |V/V_rest − 1|",
                                    PropertyRange{1e-9, 1.0}};
  Property<double> neck_level{this, "neck_level", TopologySettings{}.neck_level,
                              "f below which the island guard raises a thinning neck (field unit, 0 = off)",
                              PropertyRange{0.0, 10.0}};
  Property<double> crumb_join_level{this, "crumb_join_level", TopologySettings{}.crumb_join_level,
                                    "f to which the island guard raises the dip between a crumb and the body "
                                    "when that is a smaller change than removing it (field unit, 0 = never)",
                                    PropertyRange{0.0, 10.0}};
  Property<double> max_surface_step_mm{this, "max_surface_step_mm", StepLimitSettings{}.max_step_mm,
                                       "largest move of the surface per frame beyond where the bones carry it "
                                       "(mm, 0 = no limit)",
                                       PropertyRange{0.0, 1000.0}};
  Property<double> surface_cell_mm{this, "surface_cell_mm", 2.0, "grid cell of per-frame surfaces (mm)",
                                   PropertyRange{0.05, 50.0}};
  Property<int> fibres{this, "fibres", 100, "number of fibres (0 = none)", PropertyRange{0, 10000}};
  Property<int> fibre_segments{this, "fibre_segments", 15, "segments per fibre", PropertyRange{1, 1000}};
  Property<std::string> line_of_action_mm{this, "line_of_action_mm", std::string(),
                                          "'x y z; …' via-point path, origin body first, insertion body last "
                                          "(mm, ground at rest)"};
  Property<int> contact_probes{this, "contact_probes", 2000,
                               "probe points on the surface tested against the bones (0 = no contacts)",
                               PropertyRange{0, 1000000}};
  Property<bool> contact_response{this, "contact_response", false,
                                  "push free centres out of the bones (false: measure only)"};
  Property<double> contact_tolerance_mm{this, "contact_tolerance_mm", 0.5,
                                        "accepted penetration beyond the rest overlap (mm)", PropertyRange{1e-3, 100.0}};
  Property<int> contact_iterations_cap{this, "contact_max_iterations", 10,
                                       "cap on contact response iterations per (sub-)step", PropertyRange{0, 10000}};
  Property<int> contact_max_reseats{this, "contact_max_reseats", ContactSettings{}.max_reseats,
                                    "cap on probes re-seated per (sub-)step at bone vertices inside the muscle that no "
                                    "probe covers (0 = their depth is reported only)",
                                    PropertyRange{0, 100000}};
  Property<int> max_substeps{this, "max_substeps", 8, "cap on sub-steps per frame (tunnelling guard)",
                             PropertyRange{1, 1000}};
  BodySocket origin_body{this, "origin_body", "bone of the origin attachment"};
  BodySocket insertion_body{this, "insertion_body", "bone of the insertion attachment"};
  Output volume_mm3{this, "volume_mm3", "mm^3", "muscle volume {f > 0}", [this] { return result_.volume_mm3; }};
  Output volume_ratio{this, "volume_ratio", "1", "volume / rest volume", [this] { return result_.volume_ratio; }};
  Output volume_correction{this, "volume_correction", "1",
                           "δ: the free centres' weights are scaled by 1 + δ to keep the volume",
                           [this] { return result_.volume_correction; }};
  Output curvature_cost{this, "curvature_cost", "1", "Σ w (κ − κ₀)² after the descent, normalised",
                        [this] { return result_.curvature_cost; }};
  Output iterations{this, "iterations", "1", "descent iterations this frame", [this] { return result_.iterations; }};
  Output update_ms{this, "update_ms", "ms", "wall time of this muscle's update", [this] { return result_.update_ms; }};
  Output descent_ms{this, "descent_ms", "ms", "wall time of the descent", [this] { return result_.descent_ms; }};
  Output predict_ms{this, "predict_ms", "ms", "wall time of the prediction from the bones", [this] { return result_.predict_ms; }};
  Output volume_ms{this, "volume_ms", "ms", "wall time of the volume steps", [this] { return result_.volume_ms; }};
  Output guard_ms{this, "guard_ms", "ms", "wall time of the topology guard (islands, cavities)",
                  [this] { return result_.guard_ms; }};
  Output islands_removed{this, "islands_removed", "1", "islands and cavities the topology guard removed this frame",
                         [this] { return result_.islands_removed; }};
  Output step_excess_mm{this, "step_excess_mm", "mm",
                        "before the step limit: largest distance of a surface point from the previous frame's surface "
                        "beyond the bones' move there plus max_surface_step_mm (0 when within; max over sub-steps)",
                        [this] { return result_.step_excess_mm; }};
  Output step_scale{this, "step_scale", "1",
                    "part of the frame's correction kept by the step limit (1: all; min over sub-steps)",
                    [this] { return result_.step_scale; }};
  Output step_excess_left_mm{this, "step_excess_left_mm", "mm",
                             "the same as step_excess_mm after the step limit, before the contact response "
                             "(0 when within; max over sub-steps)",
                             [this] { return result_.step_excess_left_mm; }};
  Output islands_left{this, "islands_left", "1", "islands and cavities left (0 unless the guard hit its cap)",
                      [this] { return result_.islands_left; }};
  Output attached_centres{this, "attached_centres", "1", "centres moving rigidly with a bone",
                          [this] { return result_.attached_centres; }};

  VectorOutput fiber_length_mm{this, "fiber_length_mm", "mm", "length of each fibre",
                               [this]() -> const Eigen::VectorXd& { return result_.fiber_lengths_mm; }};
  Output fiber_length_mean_mm{this, "fiber_length_mean_mm", "mm", "mean fibre length",
                              [this] { return result_.fiber_length_mean_mm; }};
  Output fiber_length_min_mm{this, "fiber_length_min_mm", "mm", "shortest fibre",
                             [this] { return result_.fiber_length_min_mm; }};
  Output fiber_length_max_mm{this, "fiber_length_max_mm", "mm", "longest fibre",
                             [this] { return result_.fiber_length_max_mm; }};
  Output fiber_length_normalised{this, "fiber_length_normalised", "1", "mean fibre length / rest mean",
                                 [this] { return result_.fiber_length_normalised; }};
  Output fiber_projections{this, "fiber_projections", "1", "fibre points pushed back inside this frame",
                           [this] { return result_.fiber_projections; }};
  Output fiber_end_offset_max_mm{this, "fiber_end_offset_max_mm", "mm",
                                 "largest move of a fibre end off its bone-rigid place by the projection",
                                 [this] { return result_.fiber_end_offset_max_mm; }};
  Output fiber_points_outside{this, "fiber_points_outside", "1", "fibre points still outside (f ≤ 0) after projection",
                              [this] { return result_.fiber_points_outside; }};
  Output max_penetration_mm{this, "max_penetration_mm", "mm",
                            "deepest probe inside a bone beyond its rest overlap, after the response",
                            [this] { return result_.max_penetration_mm; }};
  Output max_penetration_free_mm{this, "max_penetration_free_mm", "mm",
                                 "max_penetration_mm over probes where the surface is made mostly by free centres",
                                 [this] { return result_.max_penetration_free_mm; }};
  Output max_penetration_before_mm{this, "max_penetration_before_mm", "mm",
                                   "deepest probe inside a bone beyond its rest overlap, before the response",
                                   [this] { return result_.max_penetration_before_mm; }};
  Output contacts{this, "contacts", "1", "probes inside a bone beyond their rest overlap (before the response)",
                  [this] { return result_.contacts; }};
  Output probes_off_surface{this, "probes_off_surface", "1",
                            "deepest probes left out of max_penetration_mm: off the surface after a second projection",
                            [this] { return result_.probes_off_surface; }};
  Output max_penetration_watched_mm{this, "max_penetration_watched_mm", "mm",
                                    "deepest muscle point below a bone vertex inside the muscle, before the response "
                                    "(rest overlap left out): a check of the probes",
                                    [this] { return result_.max_penetration_watched_mm; }};
  Output probes_reseated{this, "probes_reseated", "1",
                         "probes re-seated at bone vertices inside the muscle that no probe covered (summed over sub-steps)",
                         [this] { return result_.probes_reseated; }};
  Output substeps{this, "substeps", "1", "sub-steps of this frame (tunnelling guard)", [this] { return result_.substeps; }};
  Output contact_iterations{this, "contact_iterations", "1", "contact response iterations this frame",
                            [this] { return result_.contact_iterations; }};
  Output collision_ms{this, "collision_ms", "ms", "wall time of the contact handling this frame",
                      [this] { return result_.collision_ms; }};
  Output line_of_action_length_mm{this, "line_of_action_length_mm", "mm", "via-point (or straight) line-of-action length",
                                  [this] { return result_.line_of_action_length_mm; }};

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
    double volume_correction = kNaN;
    double curvature_cost = kNaN;
    double iterations = kNaN;
    double update_ms = kNaN;
    double descent_ms = kNaN;
    double predict_ms = kNaN;
    double volume_ms = kNaN;
    double guard_ms = kNaN;
    double islands_removed = kNaN;
    double islands_left = kNaN;
    double step_excess_mm = kNaN;  ///< mm
    double step_scale = kNaN;
    double step_excess_left_mm = kNaN;  ///< mm
    double attached_centres = kNaN;
    Eigen::VectorXd fiber_lengths_mm;  ///< per fibre (mm); size fixed in initialize
    double fiber_length_mean_mm = kNaN;
    double fiber_length_min_mm = kNaN;
    double fiber_length_max_mm = kNaN;
    double fiber_length_normalised = kNaN;
    double fiber_projections = kNaN;
    double fiber_points_outside = kNaN;
    double fiber_end_offset_max_mm = kNaN;
    double line_of_action_length_mm = kNaN;
    double max_penetration_mm = kNaN;         ///< mm
    double max_penetration_before_mm = kNaN;  ///< mm
    double max_penetration_free_mm = kNaN;    ///< mm
    double contacts = kNaN;
    double probes_off_surface = kNaN;
    double probes_reseated = kNaN;
    double max_penetration_watched_mm = kNaN;  ///< mm
    double substeps = kNaN;
    double contact_iterations = kNaN;
    double collision_ms = kNaN;
  };

  /// Bones (every body with a mesh), rest probes on the rest surface, their blend weights and
  /// the resolver (contact_probes > 0).
  void initializeContacts(const Skeleton& skeleton);
  /// One (sub-)step: the deformer at `motion_M`, then the contacts at `X_MB` (when enabled);
  /// `probes_carried`: carried_probes_M_ already holds the probes carried to `motion_M`.
  void step(const std::vector<Eigen::Isometry3d>& motion_M, const std::vector<Eigen::Isometry3d>& X_MB,
            bool probes_carried = false);
  /// carried_probes_M_ ← the rest probes carried by the blend of the bone motions `motion_M`.
  void carryProbes(const std::vector<Eigen::Isometry3d>& motion_M);

  /// Rest fibres and their tracker (fibres > 0), and the line-of-action path (if given).
  void initializeFibres(const Skeleton& skeleton, const GaussianField& field, const Attachments& attachments,
                        double blend_length_mm);

  Result result_;
  std::unique_ptr<MuscleDeformer> deformer_;
  std::unique_ptr<FibreTracker> fibre_tracker_;   ///< null without fibres
  std::unique_ptr<ViaPointPath> line_of_action_;  ///< null without line_of_action_mm
  Eigen::Vector3d frame_offset_mm_ = Eigen::Vector3d::Zero();  ///< origin of M in ground
  std::vector<Eigen::Isometry3d> X_GB_rest_;                    ///< origin, insertion bone poses at rest
  std::vector<Eigen::Isometry3d> bone_motion_M_;                ///< per frame, reused
  std::unique_ptr<ContactResolver> contact_resolver_;  ///< null without contact_probes
  std::unique_ptr<GaussianField> contact_field_;       ///< the resolver's work field: a copy of the deformer's, made only to push
  std::vector<int> contact_bodies_;                    ///< skeleton body of each contact bone
  Eigen::Matrix3Xd rest_probes_M_;                     ///< probes at rest (M, mm)
  Eigen::MatrixXd probe_weights_;                      ///< blend weights of the rest probes (2×P)
  Eigen::Matrix3Xd carried_probes_M_;                  ///< scratch: probes carried by the prediction
  std::vector<Eigen::Isometry3d> previous_motion_M_;   ///< bone motions of the previous frame
  std::vector<Eigen::Isometry3d> previous_X_MB_;       ///< contact bone poses of the previous frame
  std::vector<Eigen::Isometry3d> step_motion_M_, step_X_MB_, X_MB_;  ///< scratch per frame
};

}  // namespace rbfmuscle
