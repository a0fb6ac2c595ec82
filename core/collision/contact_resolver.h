#pragma once
/// @file
/// Keeps a muscle's implicit surface out of its bones: probes on f = 0, signed distances
/// to each bone by FCL-backed BoneSets, free centres moved by a minimum-norm linearised
/// correction, and the number of sub-steps a frame needs against tunnelling (issue 5,
/// DESIGN.md "Bone contacts").
#include <array>
#include <iosfwd>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "collision/bone_set.h"
#include "collision/bone_vertex_watch.h"
#include "geometry/triangle_mesh.h"
#include "rbf/gaussian_field.h"

namespace rbfmuscle {

/// One bone for a ContactResolver: its closed, outward-wound surface in its body frame B
/// (mm) and its rest pose X_MB in the muscle frame M.
struct ContactBone {
  std::string name;                                               ///< bone name (messages)
  TriangleMesh mesh_B;                                            ///< surface in B (mm)
  Eigen::Isometry3d X_MB_rest = Eigen::Isometry3d::Identity();    ///< B in M at rest (mm)
  /// Thinnest wall of the bone (mm) for the tunnelling guard; +∞ when every wall is thicker
  /// than the muscle (then only the muscle's thickness limits a sub-step).
  double thickness_mm = std::numeric_limits<double>::infinity();
};

/// Settings of a ContactResolver (lengths in mm).
struct ContactSettings {
  /// Accepted penetration beyond the rest overlap (mm): the response stops once every
  /// probe's excess depth e = −s − a ≤ this (s signed distance, a allowance, see class).
  double tolerance_mm = 0.5;
  /// How far below the tolerance a push aims (mm, > 0): the probes it moves are asked to end
  /// tolerance_mm − this deep (excess depth), so a bone pressing on gets a small push each frame
  /// instead of a push out of the bone now and then (class comment, Response). Above
  /// tolerance_mm the push aims outside the bone.
  double aim_below_tolerance_mm = 0.1;
  /// Cap on response iterations (re-project, re-query, solve) per resolve call.
  int max_iterations = 10;
  /// Newton steps per projection of a probe onto f = 0, each at most newton_step_cap_mm.
  int newton_steps = 3;
  double newton_step_cap_mm = 1.0;  ///< longest Newton step (mm)
  double projection_tolerance_mm = 0.01;  ///< |f|/‖∇f‖ at which a projection stops (mm)
  /// Probes whose certified lower bound on s − (−a) is above this are not queried (mm).
  double query_band_mm = 1.0;
  /// Damping κ of the response: μ = κ·tr(AᵀA)/m added to the diagonal of AᵀA (class
  /// comment), so near-parallel rows with different depths do not ask for huge moves.
  double damping = 0.01;
  /// Length of a push as a fraction of the local rest muscle thickness (median over the probes
  /// being pushed): the displacement field is smooth over this length, so the muscle's
  /// cross-section moves as a block rather than being dented.
  double block_fraction = 1.0;
  /// Initial trust region: largest move of one centre in one response iteration (mm); it
  /// adapts within [1/8, 4] × this value (class comment, step 5).
  double max_centre_step_mm = 2.0;
  /// Tunnelling guard: a frame is split so that no bone point near the muscle moves more
  /// than this fraction of the local muscle thickness per sub-step.
  double safe_fraction = 0.5;
  int max_substeps = 16;            ///< cap on sub-steps per frame
  double thickness_step_mm = 0.5;   ///< marching step of the rest thickness (mm)
  double thickness_max_mm = 80.0;   ///< thickness assumed where the march finds no far side (mm)
  /// Uncovered contacts (class comment): the muscle surface point below a watched bone vertex
  /// is covered by a probe that watches that bone within this distance (mm); the watched
  /// vertices are spread at twice it.
  double cover_radius_mm = 2.0;
  /// Cap on probes re-seated per resolve call. 0 (default): the bone vertices are watched and
  /// their depth reported, but no probe moves (class comment: on the hip the late pushes made
  /// surface jumps and fibre-length steps).
  int max_reseats = 0;
};

/// Why ContactResolver::resolve stopped.
enum class ContactStop {
  kWithinTolerance,  ///< every probe's excess depth ≤ tolerance (also when nothing touched)
  kIterationCap,     ///< max_iterations responses done, still a probe beyond tolerance
  kNoFreeCentre,     ///< the penetrating probes are moved by attached centres only
  kMeasureOnly       ///< resolve was asked to measure only (respond = false)
};

/// One resolve call's figures.
struct ContactReport {
  /// Probes inside a bone beyond their allowance (e > 0) at the first measurement.
  int contacts = 0;
  /// max(0, max_i e_i) at the first measurement, before any response (mm).
  double max_penetration_before_mm = 0.0;
  /// max(0, max_i e_i) at the last measurement (mm); ≤ tolerance unless the stop says otherwise.
  /// Without a push (measuring only, or nothing beyond the tolerance), over the probes on the
  /// surface (probes_off_surface).
  double max_penetration_mm = 0.0;
  /// The same over the probes where the surface is now made mostly by free centres (≥ ½ of
  /// Σ|λ_k φ_k(p)|); the others lie on attachment surface, which the response cannot move (mm).
  double max_penetration_free_mm = 0.0;
  int iterations = 0;         ///< responses (centre moves) done
  ContactStop stop = ContactStop::kWithinTolerance;  ///< why it stopped
  long long probe_queries = 0;  ///< exact (probe, bone) distance queries over all measurements
  long long projections = 0;    ///< probe projections onto f = 0 over all measurements
  int moved_centres = 0;        ///< distinct free centres moved
  /// Deepest muscle point found below a watched bone vertex, before the response: its exact
  /// depth inside that bone (mm, 0 when none; rest overlap left out; class comment, Uncovered
  /// contacts). An independent check of the probes, which can drift away from a contact.
  double max_penetration_watched_mm = 0.0;
  /// Probes re-seated at uncovered contacts (class comment) before the first measurement.
  int probes_reseated = 0;
  /// Uncovered contacts left without a probe because max_reseats was reached or no probe was free.
  int uncovered_left = 0;
  /// At the first measurement (made as when measuring only, also with the response on): probes
  /// that were the deepest left but stayed off the surface after a second, longer projection,
  /// and so were left out of the maxima (their depth is not the surface's; class comment,
  /// Measuring only).
  int probes_off_surface = 0;
  double ms = std::numeric_limits<double>::quiet_NaN();  ///< wall time (ms)
};

/// Contact handling of one muscle against a few rigid bones (all in the muscle frame M, mm).
///
/// **Probes.** P points on the rest surface f₀ = 0 (e.g. sampleSurfaceProbes of the rest
/// surface), projected onto f₀ = 0 at construction. Each frame the caller carries the rest
/// probes with the muscle's own prediction (the dual-quaternion blend of the deformer) to c_i;
/// the probe starts at x_i = p_i + (c_i − c_i^prev) (its last surface point moved by the change
/// of prediction, as the deformer's warm start) and is pulled onto the current f = 0 by
/// projectOntoSurface (≤ newton_steps · newton_step_cap_mm of travel). A response carries the
/// probes it moves. Limit: probes drift along the surface over many frames (iliacus, 1°
/// frames: some probes 20–30 mm from their carried points by 45°–60°, some into the origin
/// attachment); keeping only the normal part of the offset was tried and made the iliacus
/// response much worse (15 mm), so the drift is left as a known limit.
///
/// **Rest overlap** (the pelvis proxy overlaps the iliacus by up to 8 mm, the femoral head
/// by up to 7 mm): a probe inside bone b at rest (s_ib(rest) < 0) is excluded for that bone
/// (allowance a_ib = +∞); every other pair has a_ib = 0 and must keep s_ib ≥ −tolerance. The
/// excess depth is e_ib = −s_ib − a_ib. Chosen over the allowance a_ib = −s_ib(rest) (only
/// depth beyond the rest depth counts): measured on the hip, overlapping regions are often
/// the whole thickness of the muscle (both faces inside the proxy), where "push the surface
/// back to its rest depth" thins the muscle instead of moving it and never converges.
/// Excluded pairs are never queried; their number is in countExcludedPairs().
///
/// **Culling.** One BoneSet per bone (its own culling off: these bounds do it) gives per-bone
/// signed distances. Each (i, b) keeps the
/// reference s_ref and probe position p_ref (bone frame) of its last exact query; as s is
/// 1-Lipschitz, s_ib ≥ s_ref − ‖X_BM x − p_ref‖ − (projection travel), and the pair is
/// queried only when that bound is below −a_ib + query_band_mm. A probe with no pair to
/// query is not projected either. A pair whose reference cleared that threshold by the
/// projection's reach, and whose bound falls below it only because the probe has moved in the
/// bone frame since, is first queried again where the probe starts (the reference has aged;
/// refreshed, most such probes need no projection: iliacus, replay of the main job, about 400
/// instead of 780 projections per measuring call). Queries use the radius query_band_mm +
/// travel + 10 mm; a probe with no bone within it records the radius as its (valid) lower
/// bound. A response adds its longest centre move to the slack σ_i of every probe within reach
/// (φ ≥ 1e-3) of a moved centre: the bound also subtracts σ_i, and the next projection of that
/// probe gets ⌈σ_i / newton_step_cap_mm⌉ more Newton steps (so probes follow a surface the
/// response moved).
/// The probes to project are grouped by 10 mm cells; each group collects once the centres
/// that can be active within its probes' travel (LocalFieldEvaluator, the field's own numbers),
/// from the list of its 40 mm block.
///
/// **Measuring only** (respond = false, or measureOnly) reports the same contacts and depths
/// with less work: no query band (a pair with bound ≥ −a_ib cannot count); a pair certainly
/// inside (upper bound s_ref + ‖X_BM x − p_ref‖ < −a_ib, s_ref exact) counts without a query,
/// and a probe whose every near pair is so even after its projection travel is not projected;
/// the deepest probe (over all, and over free surface) is then found exactly by querying those
/// pairs in order of their upper bound on the excess until the best exact excess is at least
/// every remaining bound. The deepest probe must be on the surface (|f|/‖∇f‖ ≤ 0.05 mm): one
/// whose projection ran out of travel (the surface moved further than the travel since the
/// last frame) gets one projection of 30 steps and exact queries again, and is left out of the
/// maxima if still off (ContactReport::probes_off_surface); in the iliacus flexion 827 of the
/// 9255 (probe, frame) pairs deeper than 0.5 mm were such probes, none of them a frame's
/// deepest. Iliacus, main job: about 850 projections and 170 queries per frame instead of 940
/// and 440 (about 400 and 160 since the references are refreshed, above); where the time goes
/// is in models/hip/README.md ("Contacts").
///
/// **Response** (respond = true): a smooth push of the muscle out of the bones, moving free
/// centres only. Each call first measures as when measuring only; only if that finds a probe
/// beyond the tolerance does it measure again with the query band (the near probes the
/// inequalities need) and push. While some e_i = max_b e_ib > tolerance, each iteration:
///  1. rows: the probes with e_i > max(0, aim), aim = tolerance − aim_below_tolerance_mm (deepest
///     first, one per cluster of radius L/2), n_i the outward normal of the probe's deepest
///     bone; L = block_fraction × the median rest thickness of those probes, so a push moves
///     the muscle's cross-section as a block instead of denting its surface (a dent changes the
///     curvature, which the deformer's next descent undoes; with L = thickness the 1°-frame
///     iliacus loses about half as much of the push to the next descent as with the former
///     dent-shaped minimum-norm step);
///  2. displacement: free centre k moves by u_k = Σ_b ψ_k(p_b) γ_b n_b,
///     ψ_k(p) = exp(−‖ξ_k − p‖²/(L² + 1/α_k)) (the push covers each centre's own footprint);
///  3. exact first-order model: the probes are material points (a probe moves by the mean move
///     of the centres active at it, weighted by |λ_k φ_k(p)|), and the surface moves along its
///     unit gradient ĝ by t = −Δf(p)/‖∇f(p)‖, Δf(p) = Σ_k ∂f(p)/∂ξ_k · u_k, so probe a's signed
///     distance grows by Δs_a = n_a·(v_a − (ĝ_a·v_a) ĝ_a) + (ĝ_a·n_a) t_a = A_a γ. The rows ask
///     Δs_a = e_a − aim: (AᵀA + μ tr(AᵀA)/m I) γ = Aᵀ(e − aim), μ = damping. Aiming just inside
///     the tolerance rather than outside the bone: a bone that keeps pressing gets a push as
///     small as its own advance each frame; pushed 0.1 mm out of the bone, the iliacus of the
///     main job was pushed by about 0.6 mm now and then, its far side with it, and its surface
///     jumped up to 0.45 mm beyond the femur's move + 1 mm in three frames (issue 4;
///     models/hip/README.md, "Contact push aimed inside the tolerance"). (The former
///     rows f_new(p + δn) = 0 with re-projection along ∇f only gained δ c² per iteration,
///     c = cos(∇f, n): 9 % for the clamped c = 0.3, which is why they stalled on the iliacus.)
///  4. inequalities: probes near contact (within query_band_mm, not in a row) predicted to end
///     deeper than the aim join the rows with target e − aim and the system is solved
///     again (an active-set pass, at most 3 solves), so a push out of one wall of a concave
///     bone does not push the muscle into the other;
///  5. trust region: the step is scaled so no centre moves more than a limit that starts at
///     max_centre_step_mm, doubles after an iteration that lowered the worst excess and halves
///     after one that did not (within [1/8, 4] × max_centre_step_mm); the probes are carried
///     and then re-projected and re-queried (measure). When the loop stops, the best iterate
///     (lowest worst excess) is restored if the last one is worse.
/// All bones are resolved together (a probe's excess is its worst bone). Stops: ContactStop.
/// A push cannot move a surface made by attached centres: getFreeShares() gives each probe's
/// share of free centres at rest, and ContactReport::max_penetration_free_mm the penetration
/// over the probes where the surface is now made mostly by free centres.
///
/// **Tunnelling guard** (calcSubsteps): for each probe and bone that can touch this frame
/// (certified distance at the previous frame, plus allowance, below the relative move δ_ib of
/// the probe in the bone frame), the frame needs ⌈|δ_ib · n_i| / (safe_fraction · t_i)⌉
/// sub-steps, n_i the surface normal at the probe's last projection and t_i the smaller of the
/// probe's rest thickness along the inward normal (calcLocalThickness) and the bone's
/// thickness_mm. Only the move through the muscle counts: a bone point that slides along the
/// surface cannot cross its thickness (for a slab of thickness t, a move δ crosses it only if
/// |δ · n| > t). Counting the whole move |δ_ib| split 32 of the 81 1° frames of the iliacus
/// in the main job into two, where the femoral head slides under the muscle. The caller
/// interpolates the poses (interpolateScrew) and calls resolve per sub-step.
///
/// **Uncovered contacts.** Probes drift along the surface (above), and the iliacus of the main
/// job went 5.1 mm into the femur in frames where no probe was left within 5 mm (the probes
/// reported ≤ 0.5 mm). So the bones' own vertices are watched too (BoneVertexWatch: about one
/// per 2·cover_radius_mm cell, those outside the rest muscle). Before measuring, the watched
/// vertices within 10 mm of a probe that may be within 10 mm of the bone are tested; from each
/// one inside the muscle (f > 0), deepest (largest f) first, the muscle surface is followed into
/// the bone along its inward normal (marchToSurface). Where the nearest probe within
/// 3·cover_radius_mm of that point is one excluded for the bone, it is the rest overlap and
/// is left alone, as the allowances leave it; the others give max_penetration_watched_mm
/// (their exact depths, deepest first until the depth along the normal, a bound, is below the
/// best). With max_reseats > 0 such a point more than tolerance_mm deep, made mostly by free
/// centres, also gets a probe unless one that watches the bone is within cover_radius_mm and
/// measured at least its depth − tolerance/2: that near probe, else the nearest watching probe
/// not in contact, is re-seated there (its thickness and free share taken there), and the push
/// sees the penetration like any other. Off by default: on the hip the penetrations it finds
/// appear a few mm deep within one frame (the volume step bulges the muscle into the femur),
/// and pushing them out at once made surface jumps and fibre-length steps beyond issue 4's
/// and 6's bounds (figures in models/hip/README.md, "Contacts").
///
/// Limits: penetration is measured at the probes (a sharp bone edge between probes is not
/// seen); a probe whose surface point is more than the projection travel from where it
/// starts is left where the travel ends. Measured on the hip: see models/hip/README.md
/// ("Contacts").
class ContactResolver {
 public:
  /// @param bones bones with their body-frame meshes and rest poses in M (≥ 1)
  /// @param rest_field the muscle's rest field f₀ in M
  /// @param rest_probes_M 3×P probe points on or near f₀ = 0 (M, mm), P ≥ 1
  /// @param free_centres per centre of the field, true if the response may move it
  /// @throws CollisionError on no bone or probe, a mask of the wrong size, bad settings
  ///   (message names the setting), or a bone BoneSet rejects.
  ContactResolver(std::vector<ContactBone> bones, const GaussianField& rest_field,
                  const Eigen::Matrix3Xd& rest_probes_M, std::vector<bool> free_centres,
                  const ContactSettings& settings = {});

  /// Sub-steps (1 … max_substeps) the step from the last resolved poses to `X_MB` (one per
  /// bone) and carried probes `carried_M` (3×P) needs (class comment). Const.
  /// @throws CollisionError on a wrong count.
  int calcSubsteps(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::Matrix3Xd& carried_M) const;

  /// Measures, and if `respond` resolves, the contacts of `field` (M; its free centres are
  /// moved in place) with the bones at `X_MB` (B in M, one per bone), the rest probes carried
  /// to `carried_M` (3×P). The poses and carried probes become the reference of the next call.
  /// @throws CollisionError on wrong counts or a field with another number of centres.
  const ContactReport& resolve(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::Matrix3Xd& carried_M,
                               GaussianField& field, bool respond);

  /// resolve(X_MB, carried_M, ·, true) for a field it cannot change: measures `field` and, only
  /// when a push is needed, copies it into `work` (the same centres and shapes; its centres,
  /// weights and offset are overwritten) and pushes that. `work` holds the pushed field when
  /// the report's moved_centres > 0; otherwise it is untouched (no copy in most frames).
  /// @throws CollisionError as resolve, or when `work` has another number of centres.
  const ContactReport& resolveFrom(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::Matrix3Xd& carried_M,
                                   const GaussianField& field, GaussianField& work);

  /// resolve(X_MB, carried_M, field, false) for a field it cannot change: measures only
  /// (the same report, no copy of the field needed).
  const ContactReport& measureOnly(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::Matrix3Xd& carried_M,
                                   const GaussianField& field);

  /// Number of probes P.
  int countProbes() const { return static_cast<int>(probes_M_.cols()); }
  /// Number of bones B.
  int countBones() const { return static_cast<int>(bones_.size()); }
  /// Current probe points (3×P, M, mm): on f = 0 where last projected.
  const Eigen::Matrix3Xd& getProbes() const { return probes_M_; }
  /// Rest signed distances s_ib(rest) (P×B, mm; capped at the rest query radius 1e6 mm).
  const Eigen::MatrixXd& getRestSignedDistances() const { return rest_distance_mm_; }
  /// Allowances a_ib (P×B, mm): +∞ for a probe inside the bone at rest (excluded), else 0.
  const Eigen::MatrixXd& getAllowances() const { return allowance_mm_; }
  /// Number of (probe, bone) pairs excluded as rest overlap.
  int countExcludedPairs() const { return static_cast<int>((rest_distance_mm_.array() < 0.0).count()); }
  /// Free share at each probe at rest, or where it was last re-seated (P): Σ_free |λ_k φ_k(p_i)| / Σ_all |λ_k φ_k(p_i)|.
  const Eigen::VectorXd& getFreeShares() const { return free_share_; }
  /// Rest thickness t_i at each probe, or the thickness where it was last re-seated (P, mm).
  const Eigen::VectorXd& getThickness() const { return thickness_mm_; }
  /// The last report.
  const ContactReport& getReport() const { return report_; }
  /// The settings.
  const ContactSettings& getSettings() const { return settings_; }

 private:
  /// resolve, resolveFrom and measureOnly: measures `measured`; when `moved` is given and a push
  /// is needed, makes `moved` a copy of `measured` (unless it is the same field) and pushes it.
  const ContactReport& run(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::Matrix3Xd& carried_M,
                           const GaussianField& measured, GaussianField* moved);
  /// max(0, largest excess over probes whose surface is made mostly by free centres) (mm).
  double calcFreeSurfacePenetration(const GaussianField& field);
  /// Stores the unit normal of probe i from the gradient of its last projection.
  void setNormal(int i, const Eigen::Vector3d& gradient);
  /// Where probe i starts for carried points `carried_M` (class comment, Probes).
  Eigen::Vector3d calcStartPoint(int i, const Eigen::Matrix3Xd& carried_M) const;
  /// Share of Σ|λₖ φₖ(p)| made by free centres at p (0 where no centre is active);
  /// `active` is a work buffer.
  double calcFreeShare(const GaussianField& field, const Eigen::Vector3d& p_M, ActiveCentres& active) const;
  /// Projects and queries the probes that may be within the band of a bone; fills excess_.
  /// @return max(0, max_i e_i)
  /// `measure_only`: no query band, and pairs certainly inside are not queried unless they may
  /// hold the deepest probe (the contact count and the depths reported are the same).
  double measure(const GaussianField& field, bool measure_only = false);
  /// Radius of the exact queries (mm): the query band, the projection's travel and the extra
  /// reach that gives far probes a useful lower bound.
  double calcQueryRadius() const;
  /// Certified lower bound of probe i's signed distance to bone b where it is now, p_B in B
  /// (s is 1-Lipschitz: its last exact reference minus how far it has moved since).
  double calcLowerBound(int i, int b, const Eigen::Vector3d& p_B) const;
  /// Newton steps of probe i's next projection: newton_steps plus its slack in steps of the cap.
  int countNewtonSteps(int i) const;
  /// Projects the probes of project_index_ onto f = 0 of `field` (their normals too; slack cleared).
  void projectListed(const GaussianField& field);
  /// Exact signed distances of the listed probes, where they are now, to bone b (posed by X_BM,
  /// M in B), within radius_mm: they become the probes' references (ref_*); query_out_ holds
  /// the answers in list order.
  void queryReferences(int b, const std::vector<int>& probes, double radius_mm, const Eigen::Isometry3d& X_BM);
  /// Tests the watched bone vertices against `field`: the report's max_penetration_watched_mm,
  /// and probes re-seated at uncovered contacts (class comment, Uncovered contacts).
  void watchBoneVertices(const GaussianField& field);
  /// One minimum-norm response step; @return false when no free centre acts on the rows.
  bool respondOnce(GaussianField& field, double step_limit_mm);
  /// Adds `longest_mm` (the longest centre move) to the slack of the probes within the
  /// influence radius of the moved `centres` (global indices; old positions in `old_centres`).
  void addSlack(const GaussianField& field, const std::vector<int>& centres, const Eigen::Matrix3Xd& old_centres,
                double longest_mm);

  std::vector<ContactBone> bones_;
  std::vector<BoneSet> bone_sets_;  ///< one bone each: per-bone signed distances
  BoneVertexWatch watch_;           ///< the bones' vertices outside the rest muscle
  std::vector<bool> free_centres_;
  ContactSettings settings_;
  Eigen::Matrix3Xd probes_M_;        ///< p_i, current
  Eigen::Matrix3Xd normal_M_;        ///< unit ∇f/‖∇f‖ at each probe's last projection (0 where ∇f vanished)
  Eigen::Matrix3Xd carried_prev_M_;  ///< c_i of the last call
  std::vector<Eigen::Isometry3d> X_MB_prev_;
  Eigen::MatrixXd rest_distance_mm_;  ///< P×B
  Eigen::MatrixXd allowance_mm_;      ///< P×B
  Eigen::MatrixXd ref_distance_mm_;   ///< P×B lower bound of s at ref_point_B_
  Eigen::MatrixXd ref_upper_mm_;      ///< P×B upper bound of s at ref_point_B_ (+∞ when the query found no bone)
  std::vector<std::pair<int, int>> deferred_;  ///< (probe, bone) pairs certainly inside, not queried (measure only)
  Eigen::VectorXd unsure_mm_;         ///< per probe, travel of a projection not done this measurement (measure only)
  Eigen::VectorXd upper_mm_;          ///< per probe, upper bound of its excess (measure only)
  Eigen::VectorXd cutoff_radius_mm_;  ///< per centre, radius beyond which φ < ε (projection groups)
  using GroupKey = std::array<long long, 6>;  ///< block and cell of a probe to project
  std::vector<std::pair<GroupKey, int>> groups_;  ///< (key, probe) of the probes to project
  double free_penetration_mm_ = 0.0;  ///< measure only: max_penetration_free_mm of the last measurement
  std::vector<Eigen::Matrix3Xd> ref_point_B_;  ///< per bone, 3×P probe in B at its last query
  Eigen::VectorXd thickness_mm_;
  Eigen::VectorXd free_share_;         ///< per probe, free centres' share of |λφ| at rest
  Eigen::VectorXd excess_mm_;          ///< e_i of the last measurement (−∞ when not queried)
  std::vector<bool> moved_;            ///< per centre, moved in this call
  Eigen::Matrix3Xd exit_normal_M_;     ///< per probe, outward normal of its deepest bone (M)
  Eigen::VectorXd slack_mm_;           ///< per probe, how far the surface may have moved from it since its projection
  // scratch
  std::vector<int> query_index_;
  std::vector<int> project_index_;
  Eigen::Matrix3Xd query_points_;
  std::vector<ContactQueryResult> query_out_;
  std::vector<bool> relevant_;
  std::vector<int> active_;  ///< probes beyond their allowance (response)
  std::vector<int> rows_;    ///< one active probe per cluster of radius L (response)
  std::vector<int> near_;    ///< probes near contact, candidates for rows (response)
  std::vector<BoneVertexInside> inside_;  ///< watched bone vertices inside the muscle (watchBoneVertices)
  Eigen::MatrixXd psi_;      ///< N×rows push kernel ψ_k(p_b) (response)
  Eigen::Matrix3Xd best_centres_;  ///< centres of the best iterate (response)
  Eigen::Matrix3Xd best_probes_;   ///< probes of the best iterate (response)
  double last_step_mm_ = 0.0;  ///< longest centre move of the last response step (mm)
  ContactReport report_;
  std::shared_ptr<std::ofstream> dump_;  ///< RBFMUSCLE_CONTACT_DUMP record (contact_dump.h), null when off
};

}  // namespace rbfmuscle
