// Exact boundary crossings of segments: every source kind against an independent answer
// (closed form, OpenCASCADE's BRepIntCurveSurface_Inter, inside() on either side), and the
// hierarchical oracle's composite crossings against its own label() and a dense bisection.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <thread>

#include "Error.h"
#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"
#include "domain/Sphere.h"
#include "domain/TriangleSurface.h"

#include "occt_checks.h"
#include "occt_reference.h"

namespace oraclemesh {
namespace {

using test::cadDir;
using test::randomPointsAround;

// Segments between random points of the box grown by 10% (fixed seed).
std::vector<std::pair<Point3, Point3>> randomSegments(const Bbox& box, int count, unsigned seed) {
  const std::vector<Point3> ends = randomPointsAround(box, 2 * count, seed);
  std::vector<std::pair<Point3, Point3>> segments;
  for (int i = 0; i < count; ++i) segments.emplace_back(ends[2 * i], ends[2 * i + 1]);
  return segments;
}

// Sorted by t, each t in [0, 1], each point at its t, and (for one solid or surface
// component) entering and leaving in turn.
void expectWellFormed(const std::vector<BoundaryCrossing>& crossings, const Point3& a, const Point3& b,
                      double tolerance, bool alternating = true) {
  for (size_t i = 0; i < crossings.size(); ++i) {
    const BoundaryCrossing& c = crossings[i];
    EXPECT_GE(c.t, 0.0);
    EXPECT_LE(c.t, 1.0);
    EXPECT_LT(distance(c.point, a + c.t * (b - a)), tolerance);
    if (i > 0) {
      EXPECT_LE(crossings[i - 1].t, c.t);
      if (alternating)
      EXPECT_NE(crossings[i - 1].entering, c.entering)
          << "two crossings in a row in the same sense: t = " << crossings[i - 1].t << " and " << c.t << " on patches "
          << crossings[i - 1].patch << " and " << c.patch << ", segment (" << a[0] << ", " << a[1] << ", " << a[2]
          << ") -> (" << b[0] << ", " << b[1] << ", " << b[2] << ")";
    }
  }
}

// Whether the source says `entering` right: inside just after, outside just before, checked
// where the neighbouring crossings are far enough for a step off the surface.
void expectSidesMatch(const Source& source, const std::vector<BoundaryCrossing>& crossings, const Point3& a,
                      const Point3& b, double step) {
  const double length = distance(a, b);
  const double dt = step / length;
  for (size_t i = 0; i < crossings.size(); ++i) {
    const double t = crossings[i].t;
    const double gapBefore = i == 0 ? t : t - crossings[i - 1].t;
    const double gapAfter = i + 1 == crossings.size() ? 1 - t : crossings[i + 1].t - t;
    if (gapBefore > 2 * dt) EXPECT_EQ(source.inside(a + (t - dt) * (b - a)), !crossings[i].entering);
    if (gapAfter > 2 * dt) EXPECT_EQ(source.inside(a + (t + dt) * (b - a)), crossings[i].entering);
  }
}

TEST(Crossings, SphereClosedForm) {
  Sphere ball({1, 2, 3}, 2, "ball");
  auto c = ball.crossings({-4, 2, 3}, {6, 2, 3});  // through the center along x
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].t, 0.3, 1e-15);
  EXPECT_NEAR(c[1].t, 0.7, 1e-15);
  EXPECT_TRUE(c[0].entering);
  EXPECT_FALSE(c[1].entering);
  EXPECT_EQ(c[0].patch, 0);
  EXPECT_EQ(ball.crossings({1, 2, 3}, {1, 2, 13}).size(), 1u);     // from the center out
  EXPECT_TRUE(ball.crossings({-4, 4, 3}, {6, 4, 3}).empty());      // tangent: touches only
  EXPECT_TRUE(ball.crossings({-4, 2, 3}, {-3.5, 2, 3}).empty());   // stops short
  EXPECT_TRUE(ball.crossings({1, 2, 3}, {1, 2, 3}).empty());       // no length
  // Random segments: the roots lie on the sphere, and inside() agrees on either side.
  for (const auto& [a, b] : randomSegments(ball.bbox(), 500, 11)) {
    const auto crossings = ball.crossings(a, b);
    expectWellFormed(crossings, a, b, 1e-12);
    for (const BoundaryCrossing& x : crossings) EXPECT_NEAR(distance(x.point, {1, 2, 3}), 2, 1e-12);
    expectSidesMatch(ball, crossings, a, b, 1e-9);
    // The count follows from the endpoints when the segment is not near tangent.
    if (crossings.size() == 1) EXPECT_NE(ball.inside(a), ball.inside(b));
  }
}

// Two disjoint axis-aligned unit cubes (at the origin and at x = 3), 12 triangles each.
std::string twoCubesOff() {
  std::ostringstream off;
  off << "OFF\n16 24 0\n";
  for (double x0 : {0.0, 3.0})
    for (int i = 0; i < 8; ++i) off << x0 + (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int base : {0, 8})
    for (const auto& q : quads) {
      off << "3 " << base + q[0] << " " << base + q[1] << " " << base + q[2] << "\n";
      off << "3 " << base + q[0] << " " << base + q[2] << " " << base + q[3] << "\n";
    }
  return off.str();
}

TEST(Crossings, TriangleSurfaceThroughFacesEdgesAndVertices) {
  const auto path = std::filesystem::temp_directory_path() / "oraclemesh_two_cubes.off";
  std::ofstream(path) << twoCubesOff();
  const auto cubes = TriangleSurface::fromFile(path.string(), "two cubes");
  ASSERT_EQ(cubes->triangleCount(), 24u);

  // Through both cubes along x, through face interiors: enter/leave each cube once.
  auto c = cubes->crossings({-1, 0.3, 0.6}, {5, 0.3, 0.6});
  ASSERT_EQ(c.size(), 4u);
  const double expected[4] = {1 / 6.0, 2 / 6.0, 4 / 6.0, 5 / 6.0};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(c[i].t, expected[i], 1e-14);
    EXPECT_EQ(c[i].entering, i % 2 == 0);
    EXPECT_EQ(c[i].patch, i / 2) << "patch is the connected component";
  }
  // Through the diagonal of a square face (the edge between its two triangles): once each.
  c = cubes->crossings({0.5, 0.5, -1}, {0.5, 0.5, 2});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].t, 1 / 3.0, 1e-14);
  EXPECT_NEAR(c[1].t, 2 / 3.0, 1e-14);
  // Through two opposite corners (vertices shared by several triangles): once each.
  c = cubes->crossings({-0.5, -0.5, -0.5}, {1.5, 1.5, 1.5});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].t, 0.25, 1e-14);
  EXPECT_NEAR(c[1].t, 0.75, 1e-14);
  EXPECT_TRUE(c[0].entering);
  EXPECT_FALSE(c[1].entering);
  // Touching a corner from outside, and sliding along a face: no change of side.
  EXPECT_TRUE(cubes->crossings({-1, 1, 0}, {1, -1, 0}).empty());
  c = cubes->crossings({-1, 0.5, 0}, {5, 0.5, 0});  // in the plane z = 0 of both bottoms
  for (const BoundaryCrossing& x : c) EXPECT_TRUE(x.point[2] == 0);
  EXPECT_EQ(c.size() % 2, 0u);

  // Random segments: inside() agrees on either side of every crossing.
  for (const auto& [a, b] : randomSegments(cubes->bbox(), 500, 12)) {
    const auto crossings = cubes->crossings(a, b);
    expectWellFormed(crossings, a, b, 1e-12);
    expectSidesMatch(*cubes, crossings, a, b, 1e-9);
    EXPECT_EQ(crossings.size() % 2 == 1, cubes->inside(a) != cubes->inside(b));
  }
}

// BrepSolid::crossings against BRepIntCurveSurface_Inter on random segments: the same
// crossings, at the same t (within 1e-7 of the diagonal), on the same face (or on a face the
// reference hits at the same place: an edge); see test::compareWithReference.
void expectCrossingsAgreeWithOcct(const BrepSolid& solid, int count, unsigned seed) {
  const double diagonal = solid.bbox().diagonal();
  const double close = 1e-7 * diagonal;
  int solids = 0;
  for (TopExp_Explorer ex(solid.shape(), TopAbs_SOLID); ex.More(); ex.Next()) ++solids;
  test::ReferenceIntersector reference(solid.shape(), 1e-9 * diagonal);
  int total = 0, contradictions = 0;
  double oursSeconds = 0, referenceSeconds = 0;
  for (const auto& [a, b] : randomSegments(solid.bbox(), count, seed)) {
    const double length = distance(a, b);
    auto start = std::chrono::steady_clock::now();
    const std::vector<BoundaryCrossing> ours = solid.crossings(a, b);
    oursSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    start = std::chrono::steady_clock::now();
    const std::vector<test::ReferenceIntersector::Hit> hits = reference.hits(a, b);
    referenceSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const test::CrossingComparison comparison = test::compareWithReference(ours, hits, length, close, solids == 1);
    EXPECT_EQ(comparison.mismatch, "") << solid.name() << ": segment (" << a[0] << ", " << a[1] << ", " << a[2]
                                       << ") -> (" << b[0] << ", " << b[1] << ", " << b[2] << ")";
    contradictions += comparison.contradictionsLeftOut;
    expectWellFormed(ours, a, b, 1e-9 * diagonal, solids == 1);
    total += static_cast<int>(ours.size());
  }
  EXPECT_GT(total, count / 10) << "too few segments hit " << solid.name() << " to test anything";
  EXPECT_LE(contradictions, count / 50) << solid.name();
  std::cout << "[ timing   ] " << solid.name() << ": " << total << " crossings on " << count
            << " segments; crossings() " << count / oursSeconds << " segments/s, BRepIntCurveSurface_Inter "
            << count / referenceSeconds << " segments/s; " << contradictions
            << " self-contradicting reference hits left out\n";
}

// A NaN or infinite point is outside, crosses nothing and has no projection: the surface's
// CGAL queries compare exactly, and a GMP conversion of NaN raises SIGFPE.
TEST(Crossings, TriangleSurfaceIgnoresNonFinitePoints) {
  const auto path = std::filesystem::temp_directory_path() / "oraclemesh_two_cubes_nan.off";
  std::ofstream(path) << twoCubesOff();
  const auto cubes = TriangleSurface::fromFile(path.string(), "two cubes");
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Point3& p : {Point3{nan, 0.3, 0.6}, Point3{inf, 0.3, 0.6}, Point3{0.5, -inf, nan}}) {
    EXPECT_FALSE(cubes->inside(p));
    EXPECT_EQ(cubes->project(p).patch, -1);
    EXPECT_TRUE(cubes->crossings({-1, 0.3, 0.6}, p).empty());
    EXPECT_TRUE(cubes->crossings(p, {5, 0.3, 0.6}).empty());
  }
  // Finite points as before.
  EXPECT_TRUE(cubes->inside({0.5, 0.3, 0.6}));
  EXPECT_EQ(cubes->crossings({-1, 0.3, 0.6}, {5, 0.3, 0.6}).size(), 4u);
}

TEST(Crossings, BrepPrimitivesAgreeWithOcct) {
  BrepSolid box(BRepPrimAPI_MakeBox(gp_Pnt(-5, 0, 2), 10, 20, 30).Shape(), "box");
  expectCrossingsAgreeWithOcct(box, 300, 21);
  BrepSolid cylinder(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(1, 2, 3), gp_Dir(0, 0, 1)), 5, 20).Shape(), "cylinder");
  expectCrossingsAgreeWithOcct(cylinder, 300, 22);
  BrepSolid sphere(BRepPrimAPI_MakeSphere(gp_Pnt(1, 2, 3), 4).Shape(), "sphere");
  expectCrossingsAgreeWithOcct(sphere, 300, 23);
  BrepSolid torus(BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(1, 1, 0)), 10, 3).Shape(), "torus");
  expectCrossingsAgreeWithOcct(torus, 300, 24);
  // Sides: entering/leaving against the exact classifier.
  for (const auto& [a, b] : randomSegments(torus.bbox(), 100, 25))
    expectSidesMatch(torus, torus.crossings(a, b), a, b, 1e-6 * torus.bbox().diagonal());
}

// One segment against BRepIntCurveSurface_Inter (see test::compareWithReference, which
// merges hits closer than 1e-7 x diagonal into one place); a line grazing a surface enters
// and leaves closer than that, so hit for hit (same count, t, face) agrees as well. Returns
// the crossings.
std::vector<BoundaryCrossing> expectSegmentAgreesWithOcct(const BrepSolid& solid, const Point3& a, const Point3& b) {
  const double diagonal = solid.bbox().diagonal(), length = distance(a, b), close = 1e-7 * diagonal;
  test::ReferenceIntersector reference(solid.shape(), 1e-9 * diagonal);
  const std::vector<BoundaryCrossing> ours = solid.crossings(a, b);
  std::vector<test::ReferenceIntersector::Hit> hits;
  for (const auto& hit : reference.hits(a, b))
    if (!hit.tangent) hits.push_back(hit);
  bool hitForHit = hits.size() == ours.size();
  for (size_t i = 0; hitForHit && i < hits.size(); ++i)
    hitForHit = std::abs(hits[i].t - ours[i].t) * length <= close && hits[i].face == ours[i].patch &&
                hits[i].entering == ours[i].entering;
  const test::CrossingComparison comparison = test::compareWithReference(ours, hits, length, close, true);
  EXPECT_TRUE(hitForHit || (comparison.mismatch.empty() && comparison.contradictionsLeftOut == 0))
      << solid.name() << ": segment (" << a[0] << ", " << a[1] << ", " << a[2] << ") -> (" << b[0] << ", " << b[1]
      << ", " << b[2] << "): " << comparison.mismatch;
  expectWellFormed(ours, a, b, 1e-9 * diagonal);
  return ours;
}

TEST(Crossings, TangentAndNearTangentLinesOnACylinder) {
  // Radius 5 around the z axis, z in [0, 20]; its seam lies at x = 5, y = 0.
  BrepSolid cylinder(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 5, 20).Shape(), "cylinder");
  // Touching the side along x = 5 (at the seam): a touch, no crossing.
  EXPECT_TRUE(expectSegmentAgreesWithOcct(cylinder, {5, -10, 7}, {5, 10, 7}).empty());
  EXPECT_TRUE(expectSegmentAgreesWithOcct(cylinder, {-10, 5, 7}, {10, 5, 7}).empty());
  // Just outside: no crossing; just inside: two, where the closed form puts them.
  // (BRepIntCurveSurface_Inter misses the pair 1e-4 deep, 0.06 apart, that OpenCASCADE's
  // IntCurvesFace_Intersector finds.)
  EXPECT_TRUE(expectSegmentAgreesWithOcct(cylinder, {-10, 5 + 1e-6, 7}, {10, 5 + 1e-6, 7}).empty());
  for (double depth : {1e-2, 1e-4}) {
    const double y = 5 - depth, x = std::sqrt(25 - y * y);
    const auto c = depth > 1e-3 ? expectSegmentAgreesWithOcct(cylinder, {-10, y, 7}, {10, y, 7})
                                : cylinder.crossings({-10, y, 7}, {10, y, 7});
    ASSERT_EQ(c.size(), 2u) << "depth " << depth;
    EXPECT_NEAR(c[0].t, (10 - x) / 20, 1e-12);
    EXPECT_NEAR(c[1].t, (10 + x) / 20, 1e-12);
    EXPECT_TRUE(c[0].entering);
    EXPECT_FALSE(c[1].entering);
  }
  // Along the axis through both caps.
  EXPECT_EQ(expectSegmentAgreesWithOcct(cylinder, {0, 0, -5}, {0, 0, 25}).size(), 2u);
  // Through the seam edge, through the top circle, and through the vertex where they meet:
  // one crossing each, at the edge.
  for (const auto& [a, b] : {std::pair<Point3, Point3>{{10, 0, 10}, {0, 0, 10}},
                             std::pair<Point3, Point3>{{0, 10, 25}, {0, 0, 15}},
                             std::pair<Point3, Point3>{{10, 0, 25}, {0, 0, 15}}}) {
    const auto c = expectSegmentAgreesWithOcct(cylinder, a, b);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_NEAR(c[0].t, 0.5, 1e-9);
    EXPECT_TRUE(c[0].entering);
  }
}

TEST(Crossings, GrazingLinesOnATorus) {
  // Major radius 10, minor 3, around the z axis: the tube's top circle is at z = 3, its inner
  // equator at radius 7.
  BrepSolid torus(BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 10, 3).Shape(), "torus");
  // Touching the top of the tube from above, and the inner equator from inside the tube.
  EXPECT_TRUE(expectSegmentAgreesWithOcct(torus, {-20, 10, 3}, {20, 10, 3}).empty());
  EXPECT_TRUE(expectSegmentAgreesWithOcct(torus, {-5, 7, 0}, {5, 7, 0}).empty());
  // Grazing just below the top: two crossings 1.4 apart, on the torus (polished quartic
  // roots). BRepIntCurveSurface_Inter misses this pair too.
  const auto c = torus.crossings({-20, 10, 3 - 1e-4}, {20, 10, 3 - 1e-4});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(0.5 * (c[0].t + c[1].t), 0.5, 1e-9);
  for (const BoundaryCrossing& x : c) EXPECT_LT(test::distanceToShape(x.point, torus.shape()), 1e-9);
  // Through the hole along the axis: nothing; across the whole torus: four crossings.
  EXPECT_TRUE(expectSegmentAgreesWithOcct(torus, {0, 0, -10}, {0, 0, 10}).empty());
  EXPECT_EQ(expectSegmentAgreesWithOcct(torus, {-20, 0.5, 0.3}, {20, 0.5, 0.3}).size(), 4u);
  // Lines grazing the tube's outside at random points and directions along its surface.
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> angle(0, 2 * M_PI);
  for (int i = 0; i < 100; ++i) {
    const double u = angle(rng), v = angle(rng), turn = angle(rng);
    const gp_Dir radial(std::cos(u), std::sin(u), 0);
    const gp_Pnt p(gp_XYZ(0, 0, 0) + (10 + 3 * std::cos(v)) * radial.XYZ() + gp_XYZ(0, 0, 3 * std::sin(v)));
    const gp_Vec normal = gp_Vec(std::cos(v) * radial.XYZ() + gp_XYZ(0, 0, std::sin(v)));
    const gp_Vec tangentU(-std::sin(u), std::cos(u), 0), tangentV = normal.Crossed(tangentU);
    const gp_Vec along = std::cos(turn) * tangentU + std::sin(turn) * tangentV;
    const Point3 touch{p.X(), p.Y(), p.Z()}, step{along.X() * 8, along.Y() * 8, along.Z() * 8};
    expectSegmentAgreesWithOcct(torus, touch - step, touch + step);
  }
}

TEST(Crossings, BSplineFacesAgreeWithOcct) {
  // The same solids with every face converted to a B-spline surface: answered by Newton
  // iteration from the proxy triangles instead of the closed form.
  BrepSolid cylinder(
      BRepBuilderAPI_NurbsConvert(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(1, 2, 3), gp_Dir(0, 1, 1)), 5, 20).Shape())
          .Shape(),
      "B-spline cylinder");
  expectCrossingsAgreeWithOcct(cylinder, 400, 51);
  BrepSolid sphere(BRepBuilderAPI_NurbsConvert(BRepPrimAPI_MakeSphere(gp_Pnt(1, 2, 3), 4).Shape()).Shape(),
                   "B-spline sphere");
  expectCrossingsAgreeWithOcct(sphere, 400, 52);
  // (Not a B-spline torus: there OpenCASCADE's IntCurvesFace_Intersector, which crossings()
  // falls back to for segments through the tube's rim, misses crossings that
  // BRepIntCurveSurface_Inter finds, about one segment in 400, as before the closed form.)
  // Lines across the B-spline cylinder's side at mid-height, perpendicular to its axis, from
  // through the axis to grazing its side.
  const gp_XYZ axis = gp_XYZ(0, 1, 1) / std::sqrt(2.0), across = gp_XYZ(0, 1, -1) / std::sqrt(2.0);
  const gp_XYZ middle = gp_XYZ(1, 2, 3) + 10 * axis;
  for (double offset : {0.0, 2.5, 4.9, 5 - 1e-2}) {
    const gp_XYZ p = middle + offset * across;
    const auto c = expectSegmentAgreesWithOcct(cylinder, {p.X() - 10, p.Y(), p.Z()}, {p.X() + 10, p.Y(), p.Z()});
    ASSERT_EQ(c.size(), 2u) << "offset " << offset;
    const double half = std::sqrt(25 - offset * offset);
    EXPECT_NEAR(c[0].t, (10 - half) / 20, 1e-7);
    EXPECT_NEAR(c[1].t, (10 + half) / 20, 1e-7);
  }
}

TEST(Crossings, BrepEdgesAndVerticesGiveOneCrossing) {
  BrepSolid box(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 1, 1, 1).Shape(), "unit box");
  // Through an edge (x = 0, y = 0) into the box and out through the opposite one.
  auto c = box.crossings({-0.5, -0.5, 0.5}, {1.5, 1.5, 0.5});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].t, 0.25, 1e-12);
  EXPECT_NEAR(c[1].t, 0.75, 1e-12);
  EXPECT_TRUE(c[0].entering);
  EXPECT_FALSE(c[1].entering);
  // Through two opposite corners.
  c = box.crossings({-1, -1, -1}, {2, 2, 2});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].t, 1 / 3.0, 1e-12);
  EXPECT_NEAR(c[1].t, 2 / 3.0, 1e-12);
}

class CrossingsOnSharedModel : public ::testing::TestWithParam<const char*> {};

TEST_P(CrossingsOnSharedModel, AgreeWithOcct) {
  const std::string file = GetParam();
  // Each solid of the file as a source of its own, as the pipeline loads them (presse_asm.step:
  // 16 solids; its open shells are left out with a warning).
  const auto loaded = BrepSolid::loadFile(cadDir() + "/" + file, file, BrepSolid::Grouping::Separate);
  const int segments = std::max(20, 150 / static_cast<int>(loaded.solids.size()));
  for (const auto& solid : loaded.solids) expectCrossingsAgreeWithOcct(*solid, segments, 31);
}

INSTANTIATE_TEST_SUITE_P(Cad, CrossingsOnSharedModel, ::testing::ValuesIn(test::kSolidModels), test::modelTestName);

TEST(Crossings, ConcurrentQueriesGiveTheSequentialAnswers) {
  // Mesh_3 queries the oracle from several threads: the intersectors are leased per query.
  const auto solid = BrepSolid::fromFile(cadDir() + "/Kurbelwelle.stp", "Kurbelwelle");
  const auto segments = randomSegments(solid->bbox(), 400, 71);
  std::vector<std::vector<BoundaryCrossing>> sequential, parallel(segments.size());
  for (const auto& [a, b] : segments) sequential.push_back(solid->crossings(a, b));
  auto work = [&](size_t first) {
    for (size_t i = first; i < segments.size(); i += 2) parallel[i] = solid->crossings(segments[i].first, segments[i].second);
  };
  std::thread other(work, 1);
  work(0);
  other.join();
  for (size_t i = 0; i < segments.size(); ++i) {
    ASSERT_EQ(parallel[i].size(), sequential[i].size());
    for (size_t k = 0; k < parallel[i].size(); ++k) {
      EXPECT_EQ(parallel[i][k].t, sequential[i][k].t);
      EXPECT_EQ(parallel[i][k].patch, sequential[i][k].patch);
    }
  }
}

// The demo assembly as the oracle sees it: pin (material 1) over the cut box over the plate
// (material 2).
HierarchicalOracle demoOracle() {
  const test::DemoAssembly parts;
  return HierarchicalOracle({{std::make_shared<BrepSolid>(parts.pin, "pin"), Role::Material, 1},
                             {std::make_shared<BrepSolid>(parts.cut, "cut"), Role::Cut, 0},
                             {std::make_shared<BrepSolid>(parts.plate, "plate"), Role::Material, 2}});
}

// Composite crossings against label() on either side, and against a dense sampling of
// label() bisected at every change.
void expectCompositeAgreesWithLabels(const HierarchicalOracle& oracle, int count, unsigned seed) {
  const double diagonal = oracle.diagonal();
  const double close = 1e-7 * diagonal;
  const int samples = 400;
  int total = 0;
  for (const auto& [a, b] : randomSegments(oracle.bbox(), count, seed)) {
    const double length = distance(a, b);
    const auto at = [&](double t) { return a + t * (b - a); };
    const std::vector<CompositeCrossing> crossings = oracle.crossings(a, b);
    total += static_cast<int>(crossings.size());
    // Chained and consistent with label() just off each crossing.
    const double dt = 1e-6 * diagonal / length;
    for (size_t i = 0; i < crossings.size(); ++i) {
      const CompositeCrossing& c = crossings[i];
      EXPECT_NE(c.labelBefore, c.labelAfter);
      ASSERT_GE(c.entry, 0);
      EXPECT_LT(distance(c.point, at(c.t)), 1e-9 * diagonal);
      EXPECT_LT(test::distanceToShape(c.point, dynamic_cast<const BrepSolid&>(*oracle.entries()[c.entry].source)
                                                   .face(c.patch)),
                1e-7 * diagonal)
          << "crossing not on the face it names";
      if (i > 0) EXPECT_EQ(crossings[i - 1].labelAfter, c.labelBefore);
      const double gapBefore = i == 0 ? c.t : c.t - crossings[i - 1].t;
      const double gapAfter = i + 1 == crossings.size() ? 1 - c.t : crossings[i + 1].t - c.t;
      if (gapBefore > 2 * dt) EXPECT_EQ(oracle.label(at(c.t - dt)), c.labelBefore);
      if (gapAfter > 2 * dt) EXPECT_EQ(oracle.label(at(c.t + dt)), c.labelAfter);
    }
    // Dense sampling: every interval whose end labels differ holds crossings leading from one
    // to the other; a single change is bisected and found where the crossing is.
    size_t next = 0;
    int previousLabel = oracle.label(a);
    for (int s = 1; s <= samples; ++s) {
      const double t0 = double(s - 1) / samples, t1 = double(s) / samples;
      const int label = oracle.label(at(t1));
      size_t first = next;
      while (next < crossings.size() && crossings[next].t <= t1) ++next;
      if (first == next) {
        EXPECT_EQ(previousLabel, label) << "label changes between t = " << t0 << " and " << t1
                                        << " without a crossing";
      } else {
        EXPECT_EQ(crossings[first].labelBefore, previousLabel);
        EXPECT_EQ(crossings[next - 1].labelAfter, label);
        if (next - first == 1 && previousLabel != label) {
          double lo = t0, hi = t1;
          while ((hi - lo) * length > 1e-3 * close) {
            const double mid = 0.5 * (lo + hi);
            (oracle.label(at(mid)) == previousLabel ? lo : hi) = mid;
          }
          EXPECT_NEAR(crossings[first].t * length, 0.5 * (lo + hi) * length, close);
        }
      }
      previousLabel = label;
    }
  }
  EXPECT_GT(total, count);
}

TEST(CompositeCrossings, DemoAssemblyWithCutAgreesWithLabels) {
  const HierarchicalOracle oracle = demoOracle();
  expectCompositeAgreesWithLabels(oracle, 150, 41);
  // A line along y through the pin's axis region at mid-plate height: plate, pin, plate, and
  // out; then along x through the cut corner: the plate ends at the cut box, not at x = 100.
  auto c = oracle.crossings({30, -10, 5}, {30, 70, 5});
  ASSERT_EQ(c.size(), 4u);
  const int expectedLabels[5] = {0, 2, 1, 2, 0};
  const double expectedY[4] = {0, 25, 35, 60};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(c[i].labelBefore, expectedLabels[i]);
    EXPECT_EQ(c[i].labelAfter, expectedLabels[i + 1]);
    EXPECT_NEAR(c[i].point[1], expectedY[i], 1e-9);
  }
  EXPECT_EQ(c[1].entry, 0);  // the pin's boundary
  c = oracle.crossings({-10, 50, 5}, {120, 50, 5});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[1].point[0], 80, 1e-9);
  EXPECT_EQ(c[1].entry, 1);  // the cut box
  EXPECT_EQ(c[1].labelAfter, 0);
}

TEST(CompositeCrossings, OverlappingSpheresAndBoxWithCut) {
  // Sources of two kinds, with overlaps on every priority level: a cut sphere over a
  // material sphere over a box.
  HierarchicalOracle oracle({{std::make_shared<Sphere>(Point3{0, 0, 0}, 2, "hole"), Role::Cut, 0},
                             {std::make_shared<Sphere>(Point3{3, 0, 0}, 3, "ball"), Role::Material, 1},
                             {std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(-4, -4, -4), 8, 8, 8).Shape(),
                                                          "block"),
                              Role::Material, 2}});
  const double diagonal = oracle.diagonal();
  int total = 0;
  for (const auto& [a, b] : randomSegments(oracle.bbox(), 300, 51)) {
    const auto crossings = oracle.crossings(a, b);
    total += static_cast<int>(crossings.size());
    const double dt = 1e-6 * diagonal / distance(a, b);
    for (size_t i = 0; i < crossings.size(); ++i) {
      const CompositeCrossing& c = crossings[i];
      if (i > 0) EXPECT_EQ(crossings[i - 1].labelAfter, c.labelBefore);
      if (c.t > dt) EXPECT_EQ(oracle.label(a + (c.t - dt) * (b - a)), c.labelBefore);
      if (c.t < 1 - dt) EXPECT_EQ(oracle.label(a + (c.t + dt) * (b - a)), c.labelAfter);
    }
    EXPECT_EQ(crossings.empty() ? oracle.label(a) : crossings.back().labelAfter, oracle.label(b));
  }
  EXPECT_GT(total, 300);
}

}  // namespace
}  // namespace oraclemesh
