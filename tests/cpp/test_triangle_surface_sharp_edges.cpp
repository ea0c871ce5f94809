// Sharp edges of triangle surfaces as feature polylines (features/TriangleSurfaceSharpEdges).
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "discrete_shapes.h"
#include "domain/TriangleSurface.h"
#include "features/TriangleSurfaceSharpEdges.h"

namespace oraclemesh {
namespace {

std::shared_ptr<TriangleSurface> surfaceOf(const test::Triangles& t, const std::string& name) {
  return TriangleSurface::fromTriangles(t.points, t.triangles, name);
}

double lengthOf(const FeaturePolyline& pl) {
  double length = 0;
  for (size_t i = 0; i + 1 < pl.points.size(); ++i) length += distance(pl.points[i], pl.points[i + 1]);
  return length;
}

TEST(TriangleSurfaceSharpEdges, BoxHasTwelveLinesBetweenItsCorners) {
  const auto box = surfaceOf(test::triangleBox({1, 2, 3}, 40, 20, 10), "box");
  const FeatureGraph graph = extractTriangleSurfaceSharpEdges(*box, 4, 30, 3);
  ASSERT_EQ(graph.polylines.size(), 12u);
  std::map<Point3, int> ends;
  double total = 0;
  for (const FeaturePolyline& pl : graph.polylines) {
    EXPECT_EQ(pl.source, 4);
    EXPECT_EQ(pl.edge, -1);
    EXPECT_EQ(pl.junction, -1);
    EXPECT_EQ(pl.user, -1);
    ++ends[pl.points.front()];
    ++ends[pl.points.back()];
    total += lengthOf(pl);
    for (size_t i = 0; i + 1 < pl.points.size(); ++i) EXPECT_LE(distance(pl.points[i], pl.points[i + 1]), 3 * (1 + 1e-12));
    // On a box edge: two of the three coordinates at the box's faces.
    for (const Point3& p : pl.points) {
      int onFaces = 0;
      for (int k = 0; k < 3; ++k) {
        const double low = Point3{1, 2, 3}[k], high = low + Point3{40, 20, 10}[k];
        onFaces += std::abs(p[k] - low) < 1e-12 || std::abs(p[k] - high) < 1e-12;
      }
      EXPECT_GE(onFaces, 2) << p[0] << " " << p[1] << " " << p[2];
    }
  }
  EXPECT_NEAR(total, 4 * (40 + 20 + 10), 1e-9);
  EXPECT_EQ(ends.size(), 8u);
  for (const auto& [p, n] : ends) EXPECT_EQ(n, 3);
}

// The 48-gon's rims meet its sides at 90 degrees, its sides meet each other at 7.5.
TEST(TriangleSurfaceSharpEdges, CylinderRimsAreClosedLinesAndItsSidesAreSharpOnlyUnderTheirAngle) {
  const auto cylinder = surfaceOf(test::tessellatedCylinder({0, 0, 0}, 5, 20, 48), "pin");
  const FeatureGraph rims = extractTriangleSurfaceSharpEdges(*cylinder, 0, 30, 100);
  ASSERT_EQ(rims.polylines.size(), 2u);
  for (const FeaturePolyline& pl : rims.polylines) {
    EXPECT_EQ(pl.points.front(), pl.points.back()) << "a rim with no corner is a closed line";
    EXPECT_EQ(pl.points.size(), 49u);  // every rim vertex, and no split at 100
    for (const Point3& p : pl.points) {
      EXPECT_NEAR(std::hypot(p[0], p[1]), 5, 1e-12);
      EXPECT_TRUE(p[2] == 0 || p[2] == 20);
    }
  }
  EXPECT_TRUE(extractTriangleSurfaceSharpEdges(*cylinder, 0, 90.5, 100).polylines.empty());
  // At 5 degrees the sides' edges are sharp too: every rim vertex is a corner where a side
  // edge meets the rim, so the rims break into their 48 edges each, and the 48 side edges
  // are lines of their own.
  const FeatureGraph all = extractTriangleSurfaceSharpEdges(*cylinder, 0, 5, 100);
  EXPECT_EQ(all.polylines.size(), 48u * 3);
  for (const FeaturePolyline& pl : all.polylines) EXPECT_EQ(pl.points.size(), 2u);
}

// Vertices along a box edge (its top edges split at their midpoints, the top a flat fan) are
// inside their lines, not ends: still twelve lines.
TEST(TriangleSurfaceSharpEdges, VerticesAlongAnEdgeStayInsideItsLine) {
  test::Triangles split = test::triangleBox({0, 0, 0}, 30, 20, 10);
  const int64_t m01 = 8, m12 = 9, m23 = 10, m30 = 11, c = 12;
  split.points.insert(split.points.end(), {{15, 0, 10}, {30, 10, 10}, {15, 20, 10}, {0, 10, 10}, {15, 10, 10}});
  split.triangles = {{0, 2, 1},   {0, 3, 2},                                                // bottom
                     {0, 1, m01}, {0, m01, 4},  {1, 5, m01}, {1, 2, m12}, {1, m12, 5}, {2, 6, m12},
                     {2, 3, m23}, {2, m23, 6},  {3, 7, m23}, {3, 0, m30}, {3, m30, 7}, {0, 4, m30},
                     {4, m01, c}, {m01, 5, c},  {5, m12, c}, {m12, 6, c}, {6, m23, c}, {m23, 7, c},
                     {7, m30, c}, {m30, 4, c}};
  const auto surface = surfaceOf(split, "split top");
  ASSERT_NEAR(surface->volume(), 30 * 20 * 10, 1e-9);
  const FeatureGraph graph = extractTriangleSurfaceSharpEdges(*surface, 0, 30, 100);
  EXPECT_EQ(graph.polylines.size(), 12u);
  size_t throughMidpoints = 0;
  for (const FeaturePolyline& pl : graph.polylines) throughMidpoints += pl.points.size() == 3;
  EXPECT_EQ(throughMidpoints, 4u);
}

}  // namespace
}  // namespace oraclemesh
