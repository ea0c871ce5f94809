// CurveRegistry: "project p onto feature curve c" for a B-rep edge of an oracle entry and for
// a user polyline with and without its exact CAD edge; unknown curves project to nothing.
#include <gtest/gtest.h>

#include <BRepAdaptor_Curve.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>

#include <cmath>
#include <memory>
#include <vector>

#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"
#include "domain/Sphere.h"
#include "features/CurveRegistry.h"
#include "features/UserPolylines.h"

#include "occt_checks.h"

namespace oraclemesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

double radiusAboutZ(const Point3& p) { return std::hypot(p[0], p[1]); }

// A cylinder of radius 2 from z = 0 to z = 4 about the z axis (entry 0) and a sphere (entry 1).
HierarchicalOracle cylinderAndSphere(std::shared_ptr<BrepSolid>& cylinder) {
  cylinder = std::make_shared<BrepSolid>(BRepPrimAPI_MakeCylinder(2, 4).Shape(), "cylinder");
  std::vector<OracleEntry> entries;
  entries.push_back({cylinder, Role::Material, 1});
  entries.push_back({std::make_shared<Sphere>(Point3{10, 0, 0}, 1, "ball"), Role::Material, 2});
  return HierarchicalOracle(std::move(entries));
}

// The index of the cylinder's circular edge at height z.
int circleEdgeAt(const BrepSolid& solid, double z) {
  for (int i = 0; i < solid.edgeCount(); ++i) {
    BRepAdaptor_Curve curve(solid.edge(i));
    if (curve.GetType() == GeomAbs_Circle && std::abs(curve.Value(curve.FirstParameter()).Z() - z) < 1e-9) return i;
  }
  return -1;
}

TEST(CurveRegistry, ProjectsOntoTheBrepEdgeOfItsEntry) {
  std::shared_ptr<BrepSolid> cylinder;
  const HierarchicalOracle oracle = cylinderAndSphere(cylinder);
  const int top = circleEdgeAt(*cylinder, 4);
  ASSERT_GE(top, 0);
  CurveRegistry curves(oracle);
  curves.addBrepEdge(7, 0, top);
  ASSERT_TRUE(curves.contains(7));
  EXPECT_EQ(curves.entryOf(7), 0);

  // Off the top circle: outside it radially by 1 and above it by 0.5.
  const double angle = 0.3;
  const Point3 p{3 * std::cos(angle), 3 * std::sin(angle), 4.5};
  const BoundaryProjection q = curves.project(7, p);
  ASSERT_TRUE(std::isfinite(q.distance));
  EXPECT_NEAR(radiusAboutZ(q.point), 2, 1e-7);
  EXPECT_NEAR(q.point[2], 4, 1e-7);
  EXPECT_NEAR(std::atan2(q.point[1], q.point[0]), angle, 1e-7);
  EXPECT_NEAR(q.distance, std::hypot(1.0, 0.5), 1e-7);
  EXPECT_NEAR(distance(curves.ontoCurve(7, p), q.point), 0, 1e-12);

  // The bottom circle is another curve: the same point goes there when registered so.
  curves.addBrepEdge(8, 0, circleEdgeAt(*cylinder, 0));
  EXPECT_NEAR(curves.project(8, p).point[2], 0, 1e-7);
}

TEST(CurveRegistry, CurvesWithoutExactGeometryProjectToNothing) {
  std::shared_ptr<BrepSolid> cylinder;
  const HierarchicalOracle oracle = cylinderAndSphere(cylinder);
  CurveRegistry curves(oracle);
  curves.addBrepEdge(1, 1, 0);  // entry 1 is a sphere: it has no B-rep edges
  const Point3 p{1, 2, 3};
  EXPECT_FALSE(std::isfinite(curves.project(1, p).distance));
  EXPECT_EQ(curves.ontoCurve(1, p), p);
  EXPECT_FALSE(curves.contains(2));  // never registered
  EXPECT_EQ(curves.entryOf(2), -1);
  EXPECT_FALSE(std::isfinite(curves.project(2, p).distance));
  EXPECT_EQ(curves.ontoCurve(2, p), p);
}

TEST(CurveRegistry, ProjectsOntoAUserPolylinesExactEdgeElseOntoTheChords) {
  std::shared_ptr<BrepSolid> cylinder;
  const HierarchicalOracle oracle = cylinderAndSphere(cylinder);
  // A circle of radius 2 at z = 1, given as 8 chords and as its exact CAD edge.
  const gp_Circ circle(gp_Ax2(gp_Pnt(0, 0, 1), gp_Dir(0, 0, 1)), 2);
  const auto exact = UserCurve::fromBrep(test::brepText(BRepBuilderAPI_MakeEdge(circle).Edge()), "circle");
  auto polyline = std::make_shared<std::vector<Point3>>();
  for (int k = 0; k <= 8; ++k) polyline->push_back({2 * std::cos(k * kPi / 4), 2 * std::sin(k * kPi / 4), 1});

  CurveRegistry curves(oracle);
  curves.addUserPolyline(3, polyline, exact);
  curves.addUserPolyline(4, polyline, nullptr);
  EXPECT_EQ(curves.entryOf(3), -1);

  // Outside the middle of the first chord, where chord and arc are farthest apart.
  const double angle = kPi / 8;
  const Point3 p{2.5 * std::cos(angle), 2.5 * std::sin(angle), 1.2};
  const BoundaryProjection onArc = curves.project(3, p);
  EXPECT_NEAR(radiusAboutZ(onArc.point), 2, 1e-7);
  EXPECT_NEAR(onArc.point[2], 1, 1e-7);
  EXPECT_NEAR(std::atan2(onArc.point[1], onArc.point[0]), angle, 1e-7);
  EXPECT_NEAR(onArc.distance, distance(p, onArc.point), 1e-12);

  const BoundaryProjection onChord = curves.project(4, p);
  EXPECT_NEAR(radiusAboutZ(onChord.point), 2 * std::cos(kPi / 8), 1e-9);  // the chord's middle
  EXPECT_NEAR(distance(onChord.point, nearestOnPolyline(*polyline, p).point), 0, 1e-12);
  EXPECT_GT(distance(onArc.point, onChord.point), 0.1);
}

TEST(CurveRegistry, RegistersAGraphByItsPolylinesOrigins) {
  std::shared_ptr<BrepSolid> cylinder;
  const HierarchicalOracle oracle = cylinderAndSphere(cylinder);
  FeatureGraph graph;
  FeaturePolyline edge;
  edge.points = {{2, 0, 4}, {0, 2, 4}};
  edge.curve = 0;
  edge.source = 0;
  edge.edge = circleEdgeAt(*cylinder, 4);
  FeaturePolyline user;
  user.points = {{0, 0, 1}, {1, 0, 1}};
  user.curve = 1;
  user.user = 0;
  graph.polylines = {edge, user};
  CurveRegistry curves(oracle);
  curves.addPolylines(graph, nullptr, {std::make_shared<const std::vector<Point3>>(user.points)}, {nullptr});
  EXPECT_EQ(curves.entryOf(0), 0);
  EXPECT_NEAR(radiusAboutZ(curves.ontoCurve(0, {1, 1, 4})), 2, 1e-7);
  EXPECT_EQ(curves.entryOf(1), -1);
  EXPECT_EQ(curves.ontoCurve(1, {0.5, 1, 1}), (Point3{0.5, 0, 1}));
}

// The foot on a polyline every feature layer measures with (Geometry.h): its segment, the
// position along it, and the first segment where two are as near.
TEST(CurveRegistry, NearestPointOfAPolylineNamesItsSegmentAndPosition) {
  const std::vector<Point3> bend{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}};
  const PolylineFoot onSecond = nearestOnPolyline(bend, {3, 1, 0});
  EXPECT_EQ(onSecond.segment, 1u);
  EXPECT_DOUBLE_EQ(onSecond.along, 0.5);
  EXPECT_EQ(onSecond.point, (Point3{2, 1, 0}));
  EXPECT_DOUBLE_EQ(onSecond.distance, 1);
  const PolylineFoot atCorner = nearestOnPolyline(bend, {3, -1, 0});  // both segments end there
  EXPECT_EQ(atCorner.segment, 0u);
  EXPECT_DOUBLE_EQ(atCorner.along, 1);
  EXPECT_DOUBLE_EQ(atCorner.distance, std::sqrt(2.0));
  const PolylineFoot single = nearestOnPolyline({{1, 1, 1}}, {1, 1, 4});
  EXPECT_EQ(single.point, (Point3{1, 1, 1}));
  EXPECT_DOUBLE_EQ(single.distance, 3);
}

}  // namespace
}  // namespace oraclemesh
