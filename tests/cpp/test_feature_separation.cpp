// Feature curves that run close: the same arc sampled by two parts in contact is one curve, and
// distinct curves closer than the edge size get protecting balls that fit between them
// (features/CoincidentFeatures, features/FeatureSeparation).
#include <gtest/gtest.h>

#include <cmath>

#include "close_curve_shapes.h"
#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"
#include "features/BrepSharpEdges.h"
#include "features/CoincidentFeatures.h"
#include "features/CurveSampling.h"
#include "features/FeatureSeparation.h"

namespace oraclemesh {
namespace {

FeaturePolyline line(const Point3& a, const Point3& b, int pieces) {
  FeaturePolyline pl;
  for (int i = 0; i <= pieces; ++i) pl.points.push_back(a + (static_cast<double>(i) / pieces) * (b - a));
  return pl;
}

TEST(FeatureSeparation, ParallelCurvesHalfAMillimetreApartGetBallsThatFitBetweenThem) {
  FeatureGraph g;
  g.polylines = {line({0, 0, 0}, {100, 0, 0}, 10), line({0, 0.5, 0}, {100, 0.5, 0}, 7),
                 line({0, 60, 0}, {100, 60, 0}, 10)};
  const FeatureEdgeSizes sizes = localFeatureEdgeSizes(g, 20, 0.01, 1e-9);
  ASSERT_EQ(sizes.at_points.size(), 3u);
  // Mesh_3 keeps balls of non-neighbouring curves apart: radii summing to under 0.5.
  for (int i : {0, 1})
    for (double s : sizes.at_points[i]) {
      EXPECT_LE(s, 0.5 / 2.1);
      EXPECT_GE(s, 0.5 / 2.5 - 1e-12);
    }
  // 59.5 mm from the nearest: the job's edge size (the curve's length / 3 is more).
  for (double s : sizes.at_points[2]) EXPECT_EQ(s, 20);
  EXPECT_NEAR(sizes.closest_separation, 0.5, 1e-12);
  EXPECT_NEAR(sizes.smallest, 0.2, 1e-12);
}

TEST(FeatureSeparation, CurvesMeetingAtAVertexAreNeighbours) {
  // Two degrees apart at the shared vertex: neighbours bound nothing, only the length does
  // (90 / 3), and Mesh_3 shrinks the balls at the vertex itself.
  const double gap = std::tan(2.0 * 3.14159265358979323846 / 180);
  FeatureGraph g;
  g.polylines = {line({0, 0, 0}, {90, 0, 0}, 9), line({0, 0, 0}, {90, 90 * gap, 0}, 9)};
  for (const auto& sizes : localFeatureEdgeSizes(g, 20, 0.01, 1e-9).at_points)
    for (double s : sizes) EXPECT_EQ(s, 20);
  // A third curve 1 mm from the shared vertex, touching neither: it bounds both there.
  g.polylines.push_back(line({0, 1, 0}, {0, 91, 0}, 9));
  const FeatureEdgeSizes sizes = localFeatureEdgeSizes(g, 20, 0.01, 1e-9);
  EXPECT_NEAR(sizes.at_points[0].front(), 1 / 2.5, 1e-12);
  EXPECT_NEAR(sizes.at_points[2].front(), 1 / 2.5, 1e-3);  // the 2-degree curve is a little nearer
  EXPECT_EQ(sizes.at_points[0].back(), 20);
}

TEST(FeatureSeparation, SizeAlongAPolylineIsLinearBetweenItsPoints) {
  const std::vector<Point3> points = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}};
  const std::vector<double> sizes = {1, 3, 5};
  EXPECT_DOUBLE_EQ(edgeSizeOnPolyline(points, sizes, {5, 0.1, 0}), 2);
  EXPECT_DOUBLE_EQ(edgeSizeOnPolyline(points, sizes, {10.2, 7.5, 0}), 4.5);
  EXPECT_DOUBLE_EQ(segmentDistance({0, 0, 0}, {10, 0, 0}, {5, -1, 2}, {5, 1, 2}), 2);
  EXPECT_DOUBLE_EQ(segmentDistance({0, 0, 0}, {10, 0, 0}, {12, 0, 0}, {20, 0, 0}), 2);
}

// Total chord length of the polylines whose points all lie on the circle of radius r at height z.
double lengthOnCircle(const FeatureGraph& g, double z, double r) {
  double length = 0;
  for (const FeaturePolyline& pl : g.polylines) {
    const bool on = std::all_of(pl.points.begin(), pl.points.end(), [&](const Point3& p) {
      return std::abs(p[2] - z) < 1e-6 && std::abs(std::hypot(p[0], p[1]) - r) < 1e-6;
    });
    if (!on) continue;
    for (size_t k = 0; k + 1 < pl.points.size(); ++k) length += distance(pl.points[k], pl.points[k + 1]);
  }
  return length;
}

TEST(CoincidentFeatures, AnArcSampledByTwoPartsInContactIsKeptOnce) {
  std::vector<OracleEntry> entries;
  const auto shapes = test::plateWithPin();
  for (size_t i = 0; i < shapes.size(); ++i)
    entries.push_back({std::make_shared<BrepSolid>(shapes[i], i == 0 ? "plate" : "pin"), Role::Material,
                       static_cast<int>(i) + 1});
  const HierarchicalOracle oracle(entries);
  const double edgeSize = 4;
  FeatureGraph all;
  for (size_t i = 0; i < entries.size(); ++i) {
    const FeatureGraph g =
        extractSharpEdges(static_cast<const BrepSolid&>(*entries[i].source), static_cast<int>(i), 30, edgeSize);
    all.polylines.insert(all.polylines.end(), g.polylines.begin(), g.polylines.end());
  }
  const FeatureGraph clipped = clipToCompositeBoundary(all, oracle);
  const double circle = 2 * 3.14159265358979323846 * test::kPinRadius;
  // The two samplings of the bottom circle are not within rounding of each other: compared
  // chord by chord both copies stay (what Mesh_3 could not protect: they cross each other).
  EXPECT_GT(lengthOnCircle(removeCoincidentFeatures(clipped, oracle), 0, test::kPinRadius), 1.9 * circle);
  const FeatureGraph once = removeCoincidentFeatures(clipped, oracle,
                                                     2 * featureSagittaTolerance(edgeSize, oracle.diagonal()));
  EXPECT_NEAR(lengthOnCircle(once, 0, test::kPinRadius), circle, 0.01 * circle);
  // The pin's top circle, on no other part, stays whole.
  EXPECT_NEAR(lengthOnCircle(once, test::kPinLength, test::kPinRadius), circle, 0.01 * circle);
}

TEST(CoincidentFeatures, APieceOfAnEdgeIsNotAlongTheNextPieceOfTheSameEdge) {
  // One B-rep edge cut into two pieces (as where a junction ends on it) 0.05 mm before one of
  // its samples: the second piece's short first segment lies on the first piece's exact edge,
  // but beyond that piece's end, so it is not along it and must stay.
  const auto shapes = test::plateWithPin();
  const std::vector<OracleEntry> entries = {{std::make_shared<BrepSolid>(shapes[1], "pin"), Role::Material, 1}};
  const HierarchicalOracle oracle(entries);
  const double edgeSize = 4;
  const FeatureGraph sharp = extractSharpEdges(static_cast<const BrepSolid&>(*entries[0].source), 0, 30, edgeSize);
  FeatureGraph pieces;
  for (const FeaturePolyline& pl : sharp.polylines) {
    if (std::abs(pl.points.front()[2] - test::kPinLength) > 1e-9 || pl.points.size() < 4) {
      pieces.polylines.push_back(pl);
      continue;
    }
    // The cut: on the circle, 0.05 mm of arc before the polyline's fourth point.
    const double fourth = std::atan2(pl.points[3][1], pl.points[3][0]);
    const double back = std::remainder(std::atan2(pl.points[2][1], pl.points[2][0]) - fourth, 2 * 3.14159265358979323846);
    const double angle = fourth + std::copysign(0.05 / test::kPinRadius, back);
    const Point3 cut{test::kPinRadius * std::cos(angle), test::kPinRadius * std::sin(angle), test::kPinLength};
    FeaturePolyline first = pl, second = pl;
    first.points.assign(pl.points.begin(), pl.points.begin() + 3);
    first.points.push_back(cut);
    second.points.assign(1, cut);
    second.points.insert(second.points.end(), pl.points.begin() + 3, pl.points.end());
    pieces.polylines.push_back(first);
    pieces.polylines.push_back(second);
  }
  const double circle = 2 * 3.14159265358979323846 * test::kPinRadius;
  ASSERT_NEAR(lengthOnCircle(pieces, test::kPinLength, test::kPinRadius), circle, 0.01 * circle);
  const FeatureGraph kept =
      removeCoincidentFeatures(pieces, oracle, 2 * featureSagittaTolerance(edgeSize, oracle.diagonal()));
  EXPECT_NEAR(lengthOnCircle(kept, test::kPinLength, test::kPinRadius),
              lengthOnCircle(pieces, test::kPinLength, test::kPinRadius), 1e-9);
}

}  // namespace
}  // namespace oraclemesh
