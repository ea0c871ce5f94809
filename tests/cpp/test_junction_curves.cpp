// Junction curves (where the boundaries of two inputs cross) as feature polylines, and their
// joining to the sharp-edge polylines so that polylines meet only at shared end points.
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>

#include <iostream>
#include <map>
#include <set>

#include "close_curve_shapes.h"
#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"
#include "features/BrepSharpEdges.h"
#include "features/CoincidentFeatures.h"
#include "features/CurveSampling.h"
#include "features/JunctionCurves.h"

namespace oraclemesh {
namespace {

// The demo assembly: pin (material 1) through a plate (material 2), a cut box removing the
// plate's corner x > 80, y > 40. Priority: pin, cut, plate.
HierarchicalOracle demoAssembly() {
  auto pin = std::make_shared<BrepSolid>(
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(30, 30, -10), gp_Dir(0, 0, 1)), 5, 30).Shape(), "pin");
  auto cut = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(80, 40, -5), 30, 30, 20).Shape(), "cut");
  auto plate = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 100, 60, 10).Shape(), "plate");
  return HierarchicalOracle({{pin, Role::Material, 1}, {cut, Role::Cut, 0}, {plate, Role::Material, 2}});
}

FeatureGraph clippedSharpEdges(const HierarchicalOracle& oracle, double segment) {
  FeatureGraph all;
  for (size_t i = 0; i < oracle.entries().size(); ++i) {
    const auto* solid = dynamic_cast<const BrepSolid*>(oracle.entries()[i].source.get());
    FeatureGraph g = extractSharpEdges(*solid, static_cast<int>(i), 30, segment);
    all.polylines.insert(all.polylines.end(), g.polylines.begin(), g.polylines.end());
  }
  return clipToCompositeBoundary(all, oracle);
}

bool near(const Point3& a, const Point3& b, double tol = 1e-9) { return distance(a, b) <= tol; }

// A straight junction from a to b (either direction), points on the segment.
bool isSegment(const FeaturePolyline& pl, const Point3& a, const Point3& b) {
  const bool forward = near(pl.points.front(), a) && near(pl.points.back(), b);
  const bool backward = near(pl.points.front(), b) && near(pl.points.back(), a);
  if (!forward && !backward) return false;
  const Point3 d = b - a;
  for (const Point3& p : pl.points)
    if (norm(cross(p - a, d)) / norm(d) > 1e-9) return false;
  return true;
}

int countSegments(const FeatureGraph& g, const Point3& a, const Point3& b) {
  int n = 0;
  for (const FeaturePolyline& pl : g.polylines) n += isSegment(pl, a, b);
  return n;
}

// Polylines may touch only at end points, and then with bitwise-equal coordinates.
void expectMeetOnlyAtSharedEnds(const FeatureGraph& g, double diagonal) {
  auto segmentDistance = [](const Point3& p1, const Point3& q1, const Point3& p2, const Point3& q2) {
    // Sampled closest distance: enough to catch touching segments.
    double best = std::numeric_limits<double>::infinity();
    constexpr int n = 64;
    for (int i = 0; i <= n; ++i) {
      const Point3 p = p1 + (double(i) / n) * (q1 - p1);
      const Point3 d = q2 - p2;
      const double u = std::clamp(dot(p - p2, d) / dot(d, d), 0.0, 1.0);
      best = std::min(best, distance(p, p2 + u * d));
    }
    return best;
  };
  const double touch = 1e-6 * diagonal;
  for (size_t i = 0; i < g.polylines.size(); ++i)
    for (size_t j = i + 1; j < g.polylines.size(); ++j) {
      const auto& a = g.polylines[i].points;
      const auto& b = g.polylines[j].points;
      for (size_t s = 0; s + 1 < a.size(); ++s)
        for (size_t t = 0; t + 1 < b.size(); ++t) {
          if (segmentDistance(a[s], a[s + 1], b[t], b[t + 1]) > touch) continue;
          // The touching point must be an end of both polylines, bitwise shared.
          bool shared = false;
          for (const Point3& ea : {a.front(), a.back()})
            for (const Point3& eb : {b.front(), b.back()})
              if (ea == eb && (near(ea, a[s], touch) || near(ea, a[s + 1], touch))) shared = true;
          EXPECT_TRUE(shared) << "polylines " << i << " (junction " << g.polylines[i].junction << ") and " << j
                              << " (junction " << g.polylines[j].junction << ") touch at (" << a[s][0] << ", "
                              << a[s][1] << ", " << a[s][2] << ") away from a shared end";
        }
    }
}

TEST(JunctionCurves, DemoAssemblyCirclesAreCompleteAndExact) {
  const HierarchicalOracle oracle = demoAssembly();
  const JunctionCurves junctions = JunctionCurves::compute(oracle);
  const FeatureGraph g = junctions.polylines(2);
  int circles = 0;
  std::set<double> heights;
  for (const FeaturePolyline& pl : g.polylines) {
    ASSERT_GE(pl.junction, 0);
    EXPECT_EQ(pl.source, -1);
    EXPECT_EQ(pl.edge, -1);
    const auto [a, b] = junctions.entries(pl.junction);
    if (a != 0) continue;  // pin / plate junctions only
    EXPECT_EQ(b, 2);
    ++circles;
    EXPECT_EQ(pl.points.front(), pl.points.back()) << "a full circle is a closed polyline";
    EXPECT_GE(pl.points.size(), 17u);  // 31.4 mm at <= 2 mm
    for (const Point3& p : pl.points) {
      EXPECT_NEAR(std::hypot(p[0] - 30, p[1] - 30), 5, 1e-9);
      EXPECT_NEAR(p[2], pl.points.front()[2], 1e-9);
    }
    for (size_t i = 0; i + 1 < pl.points.size(); ++i) EXPECT_LE(distance(pl.points[i], pl.points[i + 1]), 2 * (1 + 1e-9));
    heights.insert(std::round(pl.points.front()[2]));
    // Vertices are put back exactly onto the circle.
    const BoundaryProjection q = junctions.projectOnCurve(pl.junction, {30, 36, pl.points.front()[2] + 0.5});
    EXPECT_NEAR(distance(q.point, {30, 35, pl.points.front()[2]}), 0, 1e-9);
  }
  EXPECT_EQ(circles, 2);
  EXPECT_EQ(heights, (std::set<double>{0, 10}));
}

TEST(JunctionCurves, DemoAssemblyCutLinesAndNothingInsideThePinOrTheCorner) {
  const HierarchicalOracle oracle = demoAssembly();
  const JunctionCurves junctions = JunctionCurves::compute(oracle);
  const FeatureGraph g = junctions.polylines(2);
  for (double z : {0.0, 10.0}) {
    EXPECT_EQ(countSegments(g, {80, 40, z}, {80, 60, z}), 1) << "cut face x = 80 on the plate face z = " << z;
    EXPECT_EQ(countSegments(g, {80, 40, z}, {100, 40, z}), 1) << "cut face y = 40 on the plate face z = " << z;
  }
  // Where the cut's faces leave the plate's side faces: convex creases through the thickness.
  EXPECT_EQ(countSegments(g, {80, 60, 0}, {80, 60, 10}), 1);
  EXPECT_EQ(countSegments(g, {100, 40, 0}, {100, 40, 10}), 1);
  EXPECT_EQ(g.polylines.size(), 8u) << "2 circles + 6 cut lines";
  for (const FeaturePolyline& pl : g.polylines)
    for (const Point3& p : pl.points) {
      EXPECT_GE(std::hypot(p[0] - 30, p[1] - 30), 5 - 1e-9) << "junction inside the pin";
      EXPECT_FALSE(p[0] > 80 + 1e-9 && p[1] > 40 + 1e-9) << "junction inside the removed corner";
    }
}

TEST(JunctionCurves, DemoAssemblyJoinsTheSharpEdgesAtSharedCorners) {
  const HierarchicalOracle oracle = demoAssembly();
  const JunctionCurves junctions = JunctionCurves::compute(oracle);
  const FeatureGraph sharp = clippedSharpEdges(oracle, 2);
  const FeatureGraph joined = joinJunctions(sharp, junctions.polylines(2), oracle, junctions);
  expectMeetOnlyAtSharedEnds(joined, oracle.diagonal());
  std::set<int> ids;
  for (const FeaturePolyline& pl : joined.polylines) EXPECT_TRUE(ids.insert(pl.curve).second);
  // Corners where junctions end on sharp edges: every polyline ending there uses one point.
  std::map<Point3, int> ends;
  for (const FeaturePolyline& pl : joined.polylines) {
    ++ends[pl.points.front()];
    ++ends[pl.points.back()];
  }
  auto endsNear = [&](const Point3& c, int* distinct) {
    int n = 0;
    *distinct = 0;
    for (const auto& [p, k] : ends)
      if (near(p, c, 1e-6)) {
        n += k;
        ++*distinct;
      }
    return n;
  };
  struct Corner {
    Point3 point;
    int polylines;
  };
  // (80,40,z): cut's vertical edge + two junction lines; (80,60,z): plate edge y = 60 (cut
  // short) + two junctions; (100,40,z): plate edge x = 100 (cut short) + two junctions.
  for (const Corner& c : {Corner{{80, 40, 0}, 3}, Corner{{80, 40, 10}, 3}, Corner{{80, 60, 0}, 3},
                          Corner{{80, 60, 10}, 3}, Corner{{100, 40, 0}, 3}, Corner{{100, 40, 10}, 3}}) {
    int distinct = 0;
    EXPECT_EQ(endsNear(c.point, &distinct), c.polylines) << c.point[0] << " " << c.point[1] << " " << c.point[2];
    EXPECT_EQ(distinct, 1) << "ends at " << c.point[0] << " " << c.point[1] << " " << c.point[2] << " differ";
  }
  int junctionPolylines = 0;
  for (const FeaturePolyline& pl : joined.polylines) junctionPolylines += pl.junction >= 0;
  EXPECT_EQ(junctionPolylines, 8);
  EXPECT_EQ(joined.polylines.size(), sharp.polylines.size() + 8);
}

TEST(JunctionCurves, OverlappingBoxes) {
  // A = [0,10]^3 over B = [5,15]^3: the section is a closed hexagon of six unit... 5 mm lines
  // on A's faces x, y, z = 10 and B's faces x, y, z = 5, all creases of the composite.
  for (int materialB : {1, 2}) {
    auto a = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(10, 10, 10).Shape(), "A");
    auto b = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(5, 5, 5), 10, 10, 10).Shape(), "B");
    const HierarchicalOracle oracle({{a, Role::Material, 1}, {b, Role::Material, materialB}});
    const JunctionCurves junctions = JunctionCurves::compute(oracle);
    const FeatureGraph g = junctions.polylines(1);
    EXPECT_EQ(g.polylines.size(), 6u) << "material of B " << materialB;
    EXPECT_EQ(countSegments(g, {10, 5, 5}, {10, 5, 10}), 1);
    EXPECT_EQ(countSegments(g, {10, 10, 5}, {10, 5, 5}), 1);
    EXPECT_EQ(countSegments(g, {10, 5, 10}, {5, 5, 10}), 1);
    EXPECT_EQ(countSegments(g, {5, 10, 5}, {10, 10, 5}), 1);
    EXPECT_EQ(countSegments(g, {5, 10, 10}, {5, 10, 5}), 1);
    EXPECT_EQ(countSegments(g, {5, 5, 10}, {5, 10, 10}), 1);
    const FeatureGraph sharp = clippedSharpEdges(oracle, 1);
    const FeatureGraph joined = joinJunctions(sharp, g, oracle, junctions);
    expectMeetOnlyAtSharedEnds(joined, oracle.diagonal());
    // Same material: A's edges inside B are gone, the junctions end on clipped edges (no
    // split). Different materials: A's three edges inside B stay (interface) and are split
    // where a junction ends on them.
    EXPECT_EQ(joined.polylines.size(), sharp.polylines.size() + 6 + (materialB == 2 ? 3 : 0))
        << "material of B " << materialB;
  }
}

TEST(JunctionCurves, TouchingBoxesGiveNoJunction) {
  // B's face x = 10 lies on A's face x = 10: coplanar faces are no crease of their own; the
  // crease along B's edges there is B's sharp edge.
  auto a = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(10, 10, 10).Shape(), "A");
  auto b = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(10, 5, 0), 10, 10, 10).Shape(), "B");
  const HierarchicalOracle oracle({{a, Role::Material, 1}, {b, Role::Material, 1}});
  EXPECT_EQ(JunctionCurves::compute(oracle).size(), 0u);
}

TEST(JunctionCurves, PinStickingOutOfThePlateSide) {
  // The pin pierces the plate's side face x = 40: its circles on the top and bottom faces are
  // arcs ending on the plate's edges, and the plate's face x = 40 meets the pin in two
  // vertical lines. Every junction end on a plate edge is shared with the cut plate edge.
  auto pin = std::make_shared<BrepSolid>(
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(40, 20, -5), gp_Dir(0, 0, 1)), 5, 20).Shape(), "pin");
  auto plate = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(40, 40, 10).Shape(), "plate");
  const HierarchicalOracle oracle({{pin, Role::Material, 1}, {plate, Role::Material, 2}});
  const JunctionCurves junctions = JunctionCurves::compute(oracle);
  const FeatureGraph g = junctions.polylines(1.5);
  EXPECT_EQ(countSegments(g, {40, 15, 0}, {40, 15, 10}), 1);
  EXPECT_EQ(countSegments(g, {40, 25, 0}, {40, 25, 10}), 1);
  int arcs = 0;
  for (const FeaturePolyline& pl : g.polylines) {
    if (std::abs(pl.points.front()[2] - pl.points.back()[2]) > 1e-9) continue;
    ++arcs;
    for (const Point3& p : pl.points) {
      EXPECT_NEAR(std::hypot(p[0] - 40, p[1] - 20), 5, 1e-9);
      EXPECT_LE(p[0], 40 + 1e-9);
    }
  }
  EXPECT_EQ(arcs, 2);
  const FeatureGraph sharp = clippedSharpEdges(oracle, 1.5);
  const FeatureGraph joined = joinJunctions(sharp, g, oracle, junctions);
  expectMeetOnlyAtSharedEnds(joined, oracle.diagonal());
  EXPECT_EQ(joined.polylines.size(), sharp.polylines.size() + g.polylines.size());
  std::map<Point3, int> ends;
  for (const FeaturePolyline& pl : joined.polylines) {
    ++ends[pl.points.front()];
    ++ends[pl.points.back()];
  }
  // The four points where the pin crosses the plate's edges x = 40: plate edge piece, arc,
  // vertical line, and the pin circle does not pass there.
  for (const Point3& c : {Point3{40, 15, 0}, Point3{40, 25, 0}, Point3{40, 15, 10}, Point3{40, 25, 10}}) {
    int n = 0, distinct = 0;
    for (const auto& [p, k] : ends)
      if (near(p, c, 1e-6)) {
        n += k;
        ++distinct;
      }
    EXPECT_EQ(distinct, 1) << c[1] << " " << c[2];
    EXPECT_EQ(n, 3) << c[1] << " " << c[2];
  }
}

TEST(JunctionCurves, PinOnTheCutFaceEndsThreeJunctionsAtOnePoint) {
  // The pin stands on the cut's face x = 80: the cut line x = 80 on the plate's top face is
  // interrupted by the pin, the pin circle on the top face survives only for x < 80 (beyond
  // it the pin's side is a smooth boundary), and the pin meets the cut face in two vertical
  // lines through the plate's thickness. At (80, 45, 10) three junctions end, each cut by a
  // third input's surface: they must share one point on all three surfaces.
  auto pin = std::make_shared<BrepSolid>(
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(80, 50, -10), gp_Dir(0, 0, 1)), 5, 30).Shape(), "pin");
  auto cut = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(80, 40, -5), 30, 30, 20).Shape(), "cut");
  auto plate = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 100, 60, 10).Shape(), "plate");
  const HierarchicalOracle oracle({{pin, Role::Material, 1}, {cut, Role::Cut, 0}, {plate, Role::Material, 2}});
  const JunctionCurves junctions = JunctionCurves::compute(oracle);
  const FeatureGraph g = junctions.polylines(2);
  for (double z : {0.0, 10.0}) {
    EXPECT_EQ(countSegments(g, {80, 40, z}, {80, 45, z}), 1);
    EXPECT_EQ(countSegments(g, {80, 55, z}, {80, 60, z}), 1);
  }
  EXPECT_EQ(countSegments(g, {80, 45, 0}, {80, 45, 10}), 1);
  EXPECT_EQ(countSegments(g, {80, 55, 0}, {80, 55, 10}), 1);
  for (const FeaturePolyline& pl : g.polylines) {
    const auto [a, b] = junctions.entries(pl.junction);
    if (a == 0 && b == 2)
      for (const Point3& p : pl.points) {
        EXPECT_NEAR(std::hypot(p[0] - 80, p[1] - 50), 5, 1e-9);
        EXPECT_LE(p[0], 80 + 1e-9) << "pin circle kept where the pin side is smooth";
      }
    for (const Point3& p : pl.points) EXPECT_GE(std::hypot(p[0] - 80, p[1] - 50), 5 - 1e-9) << "inside the pin";
  }
  const FeatureGraph joined = joinJunctions(clippedSharpEdges(oracle, 2), g, oracle, junctions);
  expectMeetOnlyAtSharedEnds(joined, oracle.diagonal());
  std::map<Point3, int> ends;
  for (const FeaturePolyline& pl : joined.polylines)
    if (pl.junction >= 0) {
      ++ends[pl.points.front()];
      ++ends[pl.points.back()];
    }
  for (const Point3& c : {Point3{80, 45, 0}, Point3{80, 55, 0}, Point3{80, 45, 10}, Point3{80, 55, 10}}) {
    int n = 0, distinct = 0;
    for (const auto& [p, k] : ends)
      if (near(p, c, 1e-6)) {
        n += k;
        ++distinct;
        EXPECT_LT(distance(p, c), 1e-9 * oracle.diagonal());
      }
    EXPECT_EQ(distinct, 1) << c[1] << " " << c[2];
    EXPECT_EQ(n, 3) << c[1] << " " << c[2];
  }
}

TEST(JunctionCurves, AJunctionAlongASharpEdgeIsNotCutIntoPieces) {
  // The junction (rod leaving the nut's face) runs all along the bore's edge, sampled more
  // coarsely: its chords come close to the edge's everywhere, which once split both curves at
  // dozens of arbitrary points, and the pieces' neighbours were then dropped as "along" each
  // other, leaving gaps in the crease (the presse's worst tets sat in them).
  const auto shapes = test::rodThroughBoreOntoNut();
  const char* names[] = {"rod", "block", "nut"};
  std::vector<OracleEntry> entries;
  for (int i = 0; i < 3; ++i)
    entries.push_back({std::make_shared<BrepSolid>(shapes[i], names[i]), Role::Material, i + 1});
  const HierarchicalOracle oracle(entries);
  const JunctionCurves junctions = JunctionCurves::compute(oracle);
  const double edgeSize = 4;
  const FeatureGraph joined = joinJunctions(clippedSharpEdges(oracle, 1), junctions.polylines(edgeSize), oracle, junctions);
  auto onCircle = [](const Point3& p) {
    return std::abs(p[2]) < 1e-9 && std::abs(std::hypot(p[0], p[1]) - test::kRodRadius) < 1e-9;
  };
  std::vector<Point3> circleEnds;
  for (const FeaturePolyline& pl : joined.polylines)
    for (const Point3& end : {pl.points.front(), pl.points.back()})
      if (onCircle(end) && std::none_of(circleEnds.begin(), circleEnds.end(), [&](const Point3& q) { return near(q, end, 1e-6); }))
        circleEnds.push_back(end);
  // The ends are the B-rep vertices of the bore's edge and of the section edges (seams), not
  // points where chords happened to pass close.
  EXPECT_GE(circleEnds.size(), 1u);
  EXPECT_LE(circleEnds.size(), 2u);

  const FeatureGraph once =
      removeCoincidentFeatures(joined, oracle, 2 * featureSagittaTolerance(edgeSize, oracle.diagonal()));
  double length = 0;
  std::map<Point3, int> ends;
  for (const FeaturePolyline& pl : once.polylines) {
    if (!std::all_of(pl.points.begin(), pl.points.end(), onCircle)) continue;
    for (size_t k = 0; k + 1 < pl.points.size(); ++k) length += distance(pl.points[k], pl.points[k + 1]);
    if (pl.points.front() == pl.points.back()) continue;
    ++ends[pl.points.front()];
    ++ends[pl.points.back()];
  }
  // Kept once, whole: as long as the circle, and the pieces close up end to end.
  const double circle = 2 * 3.14159265358979323846 * test::kRodRadius;
  EXPECT_NEAR(length, circle, 0.01 * circle);
  for (const auto& [p, n] : ends) EXPECT_EQ(n, 2) << "a loose end at (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
}

}  // namespace
}  // namespace oraclemesh
