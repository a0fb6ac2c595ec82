/// ContactResolver on analytic muscles: a Gaussian sphere (radius 10 mm, one free centre, so
/// the response can only translate it) pressed by a moving box, swept by a thin plate with and
/// without sub-steps, and overlapping a bone at rest; plus the probe helpers and the screw
/// interpolation it relies on.
#include "collision/contact_resolver.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <gtest/gtest.h>

#include "collision/collision_error.h"
#include "collision/screw_interpolation.h"
#include "collision/surface_probes.h"
#include "support/eigen_compare.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::isApprox;
constexpr double kRadius = 10.0;
const Eigen::Vector3d kAttachedCentre(100.0, 0.0, 0.0);

/// Two Gaussian spheres of radius 10 mm (λ e^{−α r²} − 5 = 0 at r = 10, α = 0.01): centre 0
/// at the origin (free), centre 1 at (100, 0, 0) (attached, far from every bone).
GaussianField makeTwoSpheres() {
  Eigen::Matrix3Xd xi(3, 2);
  xi << Eigen::Vector3d::Zero(), kAttachedCentre;
  return GaussianField(-5.0, xi, Eigen::VectorXd::Constant(2, 5.0 * std::exp(1.0)), Eigen::VectorXd::Constant(2, 0.01));
}

/// n Fibonacci points on each sphere of makeTwoSpheres (mm).
Eigen::Matrix3Xd makeProbes(int n) {
  Eigen::Matrix3Xd p(3, 2 * n);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - y * y);
    const Eigen::Vector3d u(r * std::cos(golden * i), y, r * std::sin(golden * i));
    p.col(i) = kRadius * u;
    p.col(n + i) = kAttachedCentre + kRadius * u;
  }
  return p;
}

/// A box [−a, a] × [−h, h] × [−a, a] (mm) in its body frame.
TriangleMesh makeBox(double a, double h) {
  TriangleMesh m = test::makeCube(1.0, -0.5);
  m.vertices_mm = Eigen::Vector3d(2 * a, 2 * h, 2 * a).asDiagonal() * m.vertices_mm;
  return m;
}

Eigen::Isometry3d translationY(double y) {
  return Eigen::Isometry3d(Eigen::Translation3d(0.0, y, 0.0));
}

ContactResolver makeResolver(const TriangleMesh& bone, double rest_y, const GaussianField& field,
                             double bone_thickness_mm = std::numeric_limits<double>::infinity()) {
  return ContactResolver({ContactBone{"bone", bone, translationY(rest_y), bone_thickness_mm}}, field, makeProbes(300),
                         {true, false});
}

TEST(ContactResolver, SpherePressedByMovingBoxEndsWithinToleranceAttachedCentreUnmoved) {
  GaussianField field = makeTwoSpheres();
  const double half = 50.0;
  ContactResolver resolver = makeResolver(makeBox(half, half), kRadius + 2.0 + half, field);  // bottom face y = 12
  const Eigen::Matrix3Xd carried = makeProbes(300);
  double face_y = kRadius + 2.0;
  for (int frame = 0; frame < 8; ++frame) {
    face_y -= 2.0;
    const std::vector<Eigen::Isometry3d> pose = {translationY(face_y + half)};
    EXPECT_EQ(resolver.calcSubsteps(pose, carried), 1);
    const ContactReport& r = resolver.resolve(pose, carried, field, true);
    EXPECT_EQ(r.stop, ContactStop::kWithinTolerance) << "frame " << frame;
    EXPECT_LE(r.max_penetration_mm, 0.5) << "frame " << frame;
  }
  // Face at y = −6: the sphere's top sits just below it, pushed no further than needed.
  const Eigen::Vector3d c = field.getCentres().col(0);
  EXPECT_LE(c.y() + kRadius, face_y + 0.5);
  EXPECT_GE(c.y() + kRadius, face_y - 1.0);
  EXPECT_NEAR(c.x(), 0.0, 0.3);
  EXPECT_NEAR(c.z(), 0.0, 0.3);
  EXPECT_TRUE(field.getCentres().col(1) == kAttachedCentre);
}

TEST(ContactResolver, DeepPressIsResolvedInAFewIterations) {
  // A box face 4 mm into the sphere's top in one frame: the push moves the sphere down by the
  // depth (the first-order model of the probes' signed distances is exact for a translation).
  GaussianField field = makeTwoSpheres();
  const double half = 50.0;
  ContactResolver resolver = makeResolver(makeBox(half, half), kRadius + 2.0 + half, field);
  const Eigen::Matrix3Xd carried = makeProbes(300);
  const ContactReport& r = resolver.resolve({translationY(kRadius - 4.0 + half)}, carried, field, true);
  EXPECT_NEAR(r.max_penetration_before_mm, 4.0, 0.05);
  EXPECT_EQ(r.stop, ContactStop::kWithinTolerance);
  EXPECT_LE(r.iterations, 4);
  const double top = field.getCentres()(1, 0) + kRadius;
  EXPECT_LE(top, kRadius - 4.0 + 0.5);
  EXPECT_GE(top, kRadius - 4.0 - 1.0);
}

TEST(ContactResolver, PushAimsJustInsideTheToleranceSoASlowPressGetsSmallPushes) {
  // A box face enters the sphere's top by 0.3 mm a frame. A push leaves the top
  // tolerance − aim_below_tolerance_mm deep (0.4 mm by default): the sphere then moves by
  // the face's advance, never more. Aimed 0.1 mm outside the bone instead (the former rule),
  // the first push moves it by 0.7 mm at once (the far side with it: issue 4's jumps).
  const double half = 50.0, advance = 0.3;
  for (const double aim_below : {0.1, 0.6}) {
    ContactSettings settings;
    settings.aim_below_tolerance_mm = aim_below;
    GaussianField field = makeTwoSpheres();
    ContactResolver resolver({ContactBone{"bone", makeBox(half, half), translationY(kRadius + half)}}, field,
                             makeProbes(300), {true, false}, settings);
    const Eigen::Matrix3Xd carried = makeProbes(300);
    double largest_move = 0.0;
    int pushes = 0;
    for (int frame = 1; frame <= 8; ++frame) {
      const double face_y = kRadius - advance * frame;
      const double before = field.getCentres()(1, 0);
      const ContactReport& r = resolver.resolve({translationY(face_y + half)}, carried, field, true);
      ASSERT_EQ(r.stop, ContactStop::kWithinTolerance) << "frame " << frame;
      const double depth = field.getCentres()(1, 0) + kRadius - face_y;
      if (r.iterations > 0) {
        ++pushes;
        EXPECT_NEAR(depth, settings.tolerance_mm - aim_below, 0.05) << "frame " << frame << ", aim below " << aim_below;
      }
      EXPECT_LE(depth, settings.tolerance_mm + 1e-9) << "frame " << frame;
      largest_move = std::max(largest_move, before - field.getCentres()(1, 0));
    }
    EXPECT_GE(pushes, 2) << "aim below " << aim_below;
    if (aim_below < settings.tolerance_mm)
      EXPECT_LE(largest_move, advance + 0.05);
    else
      EXPECT_NEAR(largest_move, 0.6 + aim_below - settings.tolerance_mm, 0.05);  // 0.6 deep, pushed 0.1 out
  }
}

TEST(ContactResolver, ResolveFromCopiesOnlyToPushAndMatchesResolve) {
  // The same frames resolved in place and from a const field into a work copy: identical
  // reports and fields; the work field is left alone in the frames that need no push.
  GaussianField in_place = makeTwoSpheres();
  GaussianField from = makeTwoSpheres(), work = makeTwoSpheres();
  const double half = 50.0;
  ContactResolver a = makeResolver(makeBox(half, half), kRadius + 2.0 + half, in_place);
  ContactResolver b = makeResolver(makeBox(half, half), kRadius + 2.0 + half, from);
  const Eigen::Matrix3Xd carried = makeProbes(300);
  work.setCentrePositions(Eigen::Matrix3Xd::Zero(3, work.getNumCentres()));  // marks "not copied"
  int pushes = 0;
  for (const double face_y : {20.0, 10.0, 9.0, 9.0}) {  // no contact, a press, a smaller one, none new
    const std::vector<Eigen::Isometry3d> pose = {translationY(face_y + half)};
    const ContactReport ra = a.resolve(pose, carried, in_place, true);
    const ContactReport& rb = b.resolveFrom(pose, carried, from, work);
    EXPECT_EQ(ra.max_penetration_mm, rb.max_penetration_mm) << face_y;
    EXPECT_EQ(ra.iterations, rb.iterations) << face_y;
    EXPECT_EQ(ra.contacts, rb.contacts) << face_y;
    if (rb.moved_centres > 0) {
      ++pushes;
      EXPECT_TRUE(work.getCentres() == in_place.getCentres()) << face_y;
      from.setCentrePositions(work.getCentres());  // as the plugin hands the push back to the deformer
    } else if (pushes == 0) {
      EXPECT_TRUE(work.getCentres().isZero()) << "copied without a push at " << face_y;
    }
  }
  EXPECT_GE(pushes, 1);
}

TEST(ContactResolver, FreeShareSeparatesFreeAndAttachedSurface) {
  // Probes 0…299 lie on the free sphere, 300…599 on the attached one (makeProbes).
  GaussianField field = makeTwoSpheres();
  ContactResolver resolver = makeResolver(makeBox(50, 50), 62.0, field);
  EXPECT_GT(resolver.getFreeShares().head(300).minCoeff(), 0.999);
  EXPECT_LT(resolver.getFreeShares().tail(300).maxCoeff(), 1e-3);
  // A bone pressing the attached sphere only: penetration there, none on the free surface,
  // and the response has no free centre to move.
  GaussianField attached_field = makeTwoSpheres();
  ContactResolver pressed({ContactBone{"bone", makeBox(50, 50), Eigen::Isometry3d(Eigen::Translation3d(100, 62, 0))}},
                          attached_field, makeProbes(300), {true, false});
  const ContactReport& r = pressed.resolve({Eigen::Isometry3d(Eigen::Translation3d(100, 58, 0))}, makeProbes(300),
                                           attached_field, true);
  EXPECT_NEAR(r.max_penetration_mm, 2.0, 0.05);
  EXPECT_EQ(r.max_penetration_free_mm, 0.0);
  EXPECT_EQ(r.stop, ContactStop::kNoFreeCentre);
}

TEST(ContactResolver, ThinPlateSweptThroughSphereTunnelsWithoutSubstepsAndIsCaughtWithThem) {
  const TriangleMesh plate = makeBox(30.0, 2.0);  // 60 × 4 × 60 mm
  const Eigen::Isometry3d start = translationY(14.0), end = translationY(-2.0);  // y ∈ [12, 16] → [−4, 0]
  const Eigen::Matrix3Xd carried = makeProbes(300);

  GaussianField direct = makeTwoSpheres();
  ContactResolver one_step = makeResolver(plate, 14.0, direct, 4.0);
  one_step.resolve({end}, carried, direct, true);
  // Tunnelled: the plate went through the top of the sphere, whose centre stayed above its bottom face.
  EXPECT_GT(direct.getCentres()(1, 0), -4.0);

  GaussianField guarded = makeTwoSpheres();
  ContactResolver resolver = makeResolver(plate, 14.0, guarded, 4.0);
  const int substeps = resolver.calcSubsteps({end}, carried);
  EXPECT_EQ(substeps, 8);  // 16 mm against 0.5 × min(20 mm sphere, 4 mm plate)
  for (int s = 1; s <= substeps; ++s) {
    const ContactReport& r =
        resolver.resolve({interpolateScrew(start, end, double(s) / substeps)}, carried, guarded, true);
    EXPECT_LE(r.max_penetration_mm, 0.5) << "sub-step " << s;
  }
  // Caught: the sphere was pushed below the plate (top ≤ −4 mm, within the tolerance).
  const double top = guarded.getCentres()(1, 0) + kRadius;
  EXPECT_LE(top, -4.0 + 0.5);
  EXPECT_GE(top, -4.0 - 1.5);
  EXPECT_LT(guarded.calcValue(Eigen::Vector3d(0, -2, 0)), 0.0);
  EXPECT_TRUE(guarded.getCentres().col(1) == kAttachedCentre);
}

TEST(ContactResolver, RestOverlapIsExcludedAndNotPushedFurtherMotionIs) {
  GaussianField field = makeTwoSpheres();
  const double half = 50.0, overlap = 3.0;
  const double rest_face = kRadius - overlap;  // bottom face 3 mm inside the sphere at rest
  ContactResolver resolver = makeResolver(makeBox(half, half), rest_face + half, field);
  EXPECT_NEAR(resolver.getRestSignedDistances().minCoeff(), -overlap, 0.05);
  // The cap above y = 7 (area 2πR·3 of 4πR², i.e. 15 % of the sphere's probes) is excluded.
  EXPECT_NEAR(resolver.countExcludedPairs(), 0.15 * 300, 3);
  EXPECT_EQ(resolver.getAllowances().maxCoeff(), std::numeric_limits<double>::infinity());
  const Eigen::Matrix3Xd carried = makeProbes(300);
  for (int frame = 0; frame < 3; ++frame) {
    const ContactReport& r = resolver.resolve({translationY(rest_face + half)}, carried, field, true);
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ(r.contacts, 0);
    EXPECT_LE(r.max_penetration_mm, 1e-6);
  }
  EXPECT_TRUE(field.getCentres().col(0) == Eigen::Vector3d::Zero());
  // 2 mm further in: the sphere moves down by about those 2 mm (the ring of probes that enter
  // the box leaves it again), not by the 5 mm of total depth.
  const ContactReport& r = resolver.resolve({translationY(rest_face - 2.0 + half)}, carried, field, true);
  EXPECT_LE(r.max_penetration_mm, 0.5);
  EXPECT_GT(r.max_penetration_before_mm, 1.5);
  EXPECT_LE(field.getCentres()(1, 0), -2.0 + 0.5);
  EXPECT_GE(field.getCentres()(1, 0), -2.0 - 1.0);
}

TEST(ContactResolver, MeasureOnlyLeavesTheFieldAndAttachedOnlyCannotRespond) {
  GaussianField field = makeTwoSpheres();
  ContactResolver measuring = makeResolver(makeBox(50, 50), 62.0, field);
  const ContactReport& r = measuring.resolve({translationY(50.0 + 8.0)}, makeProbes(300), field, false);
  EXPECT_EQ(r.stop, ContactStop::kMeasureOnly);
  EXPECT_NEAR(r.max_penetration_mm, 2.0, 0.05);  // face at y = 8, sphere top at 10
  EXPECT_GT(r.contacts, 0);
  EXPECT_TRUE(field.getCentres().col(0) == Eigen::Vector3d::Zero());

  ContactResolver attached({ContactBone{"bone", makeBox(50, 50), translationY(62.0)}}, field, makeProbes(300),
                           {false, false});
  EXPECT_EQ(attached.resolve({translationY(58.0)}, makeProbes(300), field, true).stop, ContactStop::kNoFreeCentre);
  EXPECT_TRUE(field.getCentres().col(0) == Eigen::Vector3d::Zero());
}

TEST(ContactResolver, MeasureOnlyCountsAndDepthsExactWhileCertainContactsAreNotQueried) {
  // The box's lower face descends into the still sphere: the probes stay where they are, so the
  // exact answer is the probes' heights above the face. Probes certainly inside from earlier
  // measurements are counted without a query (deferred) and the deepest is still exact.
  const GaussianField field = makeTwoSpheres();
  const Eigen::Matrix3Xd probes = makeProbes(300);
  ContactResolver resolver = makeResolver(makeBox(50, 50), 62.0, field);
  const Eigen::Matrix3Xd& projected = resolver.getProbes();
  long long still_queries = -1;
  int still_contacts = 0;
  double previous_face = 12.0;  // rest
  for (double face : {9.5, 8.0, 7.0, 6.0, 5.0, 5.0, 7.5}) {
    const bool still = face == previous_face;  // the bone did not move since the last measurement
    previous_face = face;
    const ContactReport& r = resolver.measureOnly({translationY(50.0 + face)}, probes, field);
    int contacts = 0;
    double deepest = 0.0;
    for (int i = 0; i < 300; ++i) {  // the free sphere's probes (the attached one is beyond the box)
      const double depth = projected(1, i) - face;
      if (depth > 1e-9) ++contacts;
      deepest = std::max(deepest, depth);
    }
    EXPECT_EQ(r.contacts, contacts) << "face at y = " << face;
    EXPECT_NEAR(r.max_penetration_mm, deepest, 1e-9) << "face at y = " << face;
    EXPECT_NEAR(r.max_penetration_free_mm, deepest, 1e-9) << "the pressed sphere is free surface";
    EXPECT_EQ(r.stop, ContactStop::kMeasureOnly);
    if (still) {
      still_queries = r.probe_queries;
      still_contacts = r.contacts;
    }
  }
  EXPECT_GT(still_contacts, 50);
  EXPECT_GE(still_queries, 0);
  EXPECT_LT(still_queries, still_contacts / 4) << "contacts certain from the last measurement are not queried again";
}

TEST(ContactResolver, MeasureOnlyCountsNoDepthOfProbesTheSurfaceLeftBehind) {
  // The free sphere drops while the carried probes stay (as when a descent moves the surface
  // further than the projection's 3 mm of travel), and the box's face comes down to y = 5.
  // Returns the report and the final height of the sphere's highest rest probe.
  const auto dropAndMeasure = [](double drop_mm) {
    const Eigen::Matrix3Xd probes = makeProbes(300);
    GaussianField field = makeTwoSpheres();
    ContactResolver resolver = makeResolver(makeBox(50, 50), 62.0, field);
    Eigen::Matrix3Xd centres = field.getCentres();
    centres.col(0) = Eigen::Vector3d(0.0, -drop_mm, 0.0);
    field.setCentrePositions(centres);
    const ContactReport report = resolver.measureOnly({translationY(50.0 + 5.0)}, probes, field);
    int top = 0;
    for (int i = 0; i < 300; ++i)
      if (probes(1, i) > probes(1, top)) top = i;
    return std::make_pair(report, resolver.getProbes()(1, top));
  };

  // 8 mm: from the old top (y = 10) three Newton steps reach y ≈ 7, inside the box, while the
  // surface (top at y = 2) is clear. The deepest probes are projected again, onto it.
  const auto [dropped, top_y] = dropAndMeasure(8.0);
  EXPECT_EQ(dropped.max_penetration_mm, 0.0);
  EXPECT_EQ(dropped.max_penetration_free_mm, 0.0);
  EXPECT_EQ(dropped.probes_off_surface, 0);
  EXPECT_NEAR(top_y, 2.0, 0.05) << "the top probe is back on the surface";

  // 60 mm: beyond the centre's cut-off radius (43 mm) ∇f = 0 at the old probes, so no
  // projection moves them: they are contacts, counted off the surface, and give no depth.
  const ContactReport gone = dropAndMeasure(60.0).first;
  EXPECT_GT(gone.contacts, 0);
  EXPECT_GT(gone.probes_off_surface, 0);
  EXPECT_EQ(gone.max_penetration_mm, 0.0);
}

TEST(ContactResolver, ProbesClearOfABoneSlidingPastAreRequeriedNotProjected) {
  // The box's bottom face stays 6 mm above the sphere (more than the 3 mm projection travel)
  // while the box slides 1 mm per frame along it: every reference ages by 1 mm a frame, and
  // is refreshed by a query instead of making the probes be projected.
  GaussianField field = makeTwoSpheres();
  const double half = 50.0, gap = 6.0;
  ContactResolver resolver = makeResolver(makeBox(half, half), kRadius + gap + half, field);
  const Eigen::Matrix3Xd carried = makeProbes(300);
  long long queries = 0;
  for (int frame = 1; frame <= 20; ++frame) {
    const Eigen::Isometry3d pose(Eigen::Translation3d(frame * 1.0, kRadius + gap + half, 0.0));
    const ContactReport& r = resolver.measureOnly({pose}, carried, field);
    EXPECT_EQ(r.projections, 0) << "frame " << frame;
    EXPECT_EQ(r.contacts, 0) << "frame " << frame;
    queries += r.probe_queries;
  }
  EXPECT_GT(queries, 0);  // the references were refreshed
}

/// The free sphere's probes below y = 5 mm only and all of the attached sphere's: no probe on
/// the free sphere's top cap (radius 8.7 mm), the nearest 10 mm from its top point.
Eigen::Matrix3Xd makeProbesWithoutTop(int n) {
  const Eigen::Matrix3Xd all = makeProbes(n);
  std::vector<int> keep;
  for (int i = 0; i < all.cols(); ++i)
    if (i >= n || all(1, i) < 5.0) keep.push_back(i);
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(keep.size()));
  for (size_t k = 0; k < keep.size(); ++k) out.col(static_cast<Eigen::Index>(k)) = all.col(keep[k]);
  return out;
}

/// Deepest bone vertex inside `field`: the distance from it along the bone's inward normal
/// (the icosphere's, towards its centre c) to the muscle surface (mm; 0 when none is inside).
double calcDeepestVertexDepth(const GaussianField& field, const TriangleMesh& sphere, const Eigen::Vector3d& c) {
  double deepest = 0.0;
  for (int v = 0; v < sphere.countVertices(); ++v) {
    const Eigen::Vector3d p = c + sphere.vertices_mm.col(v);
    if (field.calcValue(p) > 0.0)
      deepest = std::max(deepest, marchToSurface(field, p, (c - p).normalized(), 0.05, 20.0));
  }
  return deepest;
}

TEST(ContactResolver, BoneVerticesInsideTheMuscleWhereNoProbeIsAreMeasuredAndGetAProbe) {
  // A round bone (radius 20 mm) comes down 3 mm into the top of the free sphere, where there
  // is no probe: the probes see nothing, the watched bone vertices measure the 3 mm; with
  // re-seating on, a probe is moved to the muscle surface below them and the push clears it.
  const TriangleMesh bone = test::makeIcosphere(20.0, 4);
  const Eigen::Vector3d down(0.0, kRadius + 20.0 - 3.0, 0.0);
  const std::vector<Eigen::Isometry3d> pose = {translationY(down.y())};
  const Eigen::Matrix3Xd probes = makeProbesWithoutTop(300);
  GaussianField field = makeTwoSpheres();
  ContactResolver measuring({ContactBone{"bone", bone, translationY(100.0)}}, field, probes, {true, false});
  const ContactReport& seen = measuring.resolve(pose, probes, field, true);
  EXPECT_EQ(seen.contacts, 0);
  EXPECT_EQ(seen.probes_reseated, 0);
  EXPECT_EQ(seen.moved_centres, 0);
  EXPECT_NEAR(seen.max_penetration_watched_mm, 3.0, 0.05);
  EXPECT_NEAR(calcDeepestVertexDepth(field, bone, down), 3.0, 0.05);  // an independent look

  ContactSettings reseating;
  reseating.max_reseats = 32;
  ContactResolver watching({ContactBone{"bone", bone, translationY(100.0)}}, field, probes, {true, false}, reseating);
  const ContactReport& measured = watching.measureOnly(pose, probes, field);
  EXPECT_GE(measured.probes_reseated, 1);
  EXPECT_NEAR(measured.max_penetration_mm, 3.0, 0.1);
  const ContactReport& pushed = watching.resolve(pose, probes, field, true);
  EXPECT_EQ(pushed.stop, ContactStop::kWithinTolerance);
  EXPECT_LE(pushed.max_penetration_mm, 0.5);
  EXPECT_LE(watching.measureOnly(pose, probes, field).max_penetration_watched_mm, 0.5 + 0.1);  // after the push
  EXPECT_LE(calcDeepestVertexDepth(field, bone, down), 0.5 + 0.1);
  EXPECT_LT(field.getCentres()(1, 0), -2.0);  // the sphere moved down, away from the bone
}

TEST(ContactResolver, BoneOverlappingTheMuscleAtRestIsNotWatchedThere) {
  // The same bone 3 mm into the sphere already at rest: its vertices inside the rest muscle
  // are not watched and the overlap is kept, as the probes' allowances keep it.
  const TriangleMesh bone = test::makeIcosphere(20.0, 4);
  const Eigen::Isometry3d overlap = translationY(kRadius + 20.0 - 3.0);
  GaussianField field = makeTwoSpheres();
  const Eigen::Matrix3Xd probes = makeProbesWithoutTop(300);
  ContactSettings reseating;
  reseating.max_reseats = 32;
  ContactResolver resolver({ContactBone{"bone", bone, overlap}}, field, probes, {true, false}, reseating);
  const ContactReport& r = resolver.resolve({overlap}, probes, field, true);
  EXPECT_EQ(r.max_penetration_watched_mm, 0.0);
  EXPECT_EQ(r.probes_reseated, 0);
  EXPECT_EQ(r.moved_centres, 0);
}

TEST(ContactResolver, BadInputNamesTheFault) {
  const GaussianField field = makeTwoSpheres();
  // Each bad setting is rejected with its name in the message.
  const auto expectRejected = [&](const ContactSettings& settings, const std::string& name) {
    try {
      ContactResolver({ContactBone{"bone", makeBox(5, 5), translationY(50)}}, field, makeProbes(10), {true, false},
                      settings);
      ADD_FAILURE() << "expected CollisionError naming " << name;
    } catch (const CollisionError& e) {
      // "ContactSettings: <name> =": "tolerance_mm" alone would also match "aim_below_tolerance_mm".
      EXPECT_NE(std::string(e.what()).find("ContactSettings: " + name + " ="), std::string::npos) << e.what();
    }
  };
  ContactSettings settings;
  settings.tolerance_mm = -1.0;
  expectRejected(settings, "tolerance_mm");
  settings = {};
  settings.cover_radius_mm = 0.0;
  expectRejected(settings, "cover_radius_mm");
  settings = {};
  settings.aim_below_tolerance_mm = 0.0;  // a push aimed at the tolerance itself need never end
  expectRejected(settings, "aim_below_tolerance_mm");
  EXPECT_THROW(ContactResolver({ContactBone{"bone", makeBox(5, 5), translationY(50)}}, field, makeProbes(10), {true}),
               CollisionError);
  EXPECT_THROW(ContactResolver({}, field, makeProbes(10), {true, false}), CollisionError);
}

TEST(SurfaceProbes, ProjectionThicknessAndSampling) {
  const GaussianField field = makeTwoSpheres();
  Eigen::Vector3d x(3.0, 4.0, 5.0);  // inside, 7.07 mm from the centre
  EXPECT_TRUE(projectOntoSurface(field, x, 20, 2.0, 1e-6));
  EXPECT_NEAR(x.norm(), kRadius, 1e-5);
  EXPECT_NEAR(calcLocalThickness(field, Eigen::Vector3d(0, kRadius, 0), 0.5, 80.0), 2 * kRadius, 1e-4);
  Eigen::Vector3d far(0.0, 30.0, 0.0);
  EXPECT_FALSE(projectOntoSurface(field, far, 2, 1.0, 1e-6));
  EXPECT_NEAR(far.y(), 28.0, 1e-12);  // two capped steps of 1 mm

  const TriangleMesh sphere = test::makeIcosphere(kRadius, 4);  // 2562 vertices
  const Eigen::Matrix3Xd probes = sampleSurfaceProbes(sphere, 500);
  EXPECT_LE(probes.cols(), 500);
  EXPECT_GE(probes.cols(), 400);
  EXPECT_EQ(sampleSurfaceProbes(sphere, 100000).cols(), sphere.countVertices());
  EXPECT_THROW(sampleSurfaceProbes(sphere, 0), std::invalid_argument);
}

TEST(SurfaceProbes, LocalFieldEvaluatorGivesTheFieldsNumbersBitwise) {
  // Centres of very different widths around a probe group; at points within the collected
  // radius the local sum equals calcValueAndGradient bit for bit (same test, same order).
  Eigen::Matrix3Xd xi = Eigen::Matrix3Xd::Random(3, 200) * 40.0;
  Eigen::VectorXd lambda = Eigen::VectorXd::Random(200);
  Eigen::VectorXd alpha(200);
  for (int k = 0; k < 200; ++k) alpha(k) = std::pow(10.0, -1.5 + 2.5 * Eigen::Vector2d::Random()(0));  // 10^-4 … 10 mm⁻²
  const GaussianField field(-0.1, xi, lambda, alpha);
  const Eigen::VectorXd cutoff_radius = (-std::log(field.getCutoff()) / alpha.array()).sqrt();
  const Eigen::Vector3d c(3.0, -2.0, 1.0);
  LocalFieldEvaluator evaluate;
  evaluate.collect(field, cutoff_radius, c, 6.0);
  EXPECT_LT(evaluate.size(), field.getNumCentres());
  for (int j = 0; j < 50; ++j) {
    const Eigen::Vector3d x = c + 6.0 * Eigen::Vector3d::Random().normalized() * (j / 50.0);
    Eigen::Vector3d g_local, g_field;
    EXPECT_EQ(evaluate(x, g_local), calcValueAndGradient(field, x, g_field));
    EXPECT_TRUE(g_local == g_field) << g_local.transpose() << " vs " << g_field.transpose();
  }
}

TEST(ScrewInterpolation, RotationAboutAPointFollowsTheArc) {
  const Eigen::Vector3d c(143.0, 243.0, -432.0), axis = Eigen::Vector3d(0.2, 0.1, 1.0).normalized();
  const auto about = [&](double angle) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    X.translation() = c - X.linear() * c + 3.0 * angle * axis;  // a screw: rotation plus slide
    return X;
  };
  const Eigen::Isometry3d a = about(0.2), b = about(1.0);
  EXPECT_TRUE(isApprox(interpolateScrew(a, b, 0.0).matrix(), a.matrix(), 1e-9));
  EXPECT_TRUE(isApprox(interpolateScrew(a, b, 1.0).matrix(), b.matrix(), 1e-9));
  EXPECT_TRUE(isApprox(interpolateScrew(a, b, 0.25).matrix(), about(0.4).matrix(), 1e-9));
  const Eigen::Isometry3d t0(Eigen::Translation3d(1, 2, 3)), t1(Eigen::Translation3d(5, 2, 3));
  EXPECT_TRUE(isApprox(interpolateScrew(t0, t1, 0.5).translation(), Eigen::Vector3d(3, 2, 3), 1e-12));
}

}  // namespace
}  // namespace rbfmuscle
