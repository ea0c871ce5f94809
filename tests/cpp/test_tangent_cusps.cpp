// Curves leaving a vertex tangentially (features/TangentCusps.h) on hand-made polylines: a line
// and the parabola y = x^2 / 20 tangent to it at the origin, whose gap grows as x^2 / 20.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "features/TangentCusps.h"

namespace oraclemesh {
namespace {

constexpr double kCurvature = 0.05;  // y = kCurvature x^2

FeaturePolyline sampled(const std::vector<double>& xs, double curvature, int edge) {
  FeaturePolyline pl;
  for (double x : xs) pl.points.push_back({x, curvature * x * x, 0});
  pl.source = 0;
  pl.edge = edge;
  pl.curve = edge;
  return pl;
}

std::vector<double> range(double from, double to, double step) {
  std::vector<double> xs;
  for (double x = from; x <= to + 1e-12; x += step) xs.push_back(x);
  return xs;
}

// The exact tangents: the curves are y = c x^2 with c = 0 (line) or kCurvature, so the
// direction at x is (1, 2 c x), signed to run into the polyline.
Point3 exactLeaving(const FeaturePolyline& pl, bool atBack) {
  const Point3& end = atBack ? pl.points.back() : pl.points.front();
  const Point3& next = atBack ? pl.points[pl.points.size() - 2] : pl.points[1];
  const double c = pl.edge == 1 ? kCurvature : 0;
  Point3 t{1, 2 * c * end[0], 0};
  if (dot(t, next - end) < 0) t = -1.0 * t;
  return (1 / norm(t)) * t;
}

const auto kEdgeSize = [](const Point3&) { return 2.0; };

int endsAt(const FeatureGraph& graph, const Point3& p) {
  int n = 0;
  for (const FeaturePolyline& pl : graph.polylines) n += (pl.points.front() == p) + (pl.points.back() == p);
  return n;
}

TEST(TangentCusps, TheShorterCurveStartsOnTheLongerWhereTheyPartByAQuarterOfTheEdgeSize) {
  FeatureGraph graph;
  graph.polylines = {sampled(range(0, 10, 2), 0, 0), sampled(range(0, 8, 2), kCurvature, 1)};
  std::vector<TangentCusp> cusps;
  const FeatureGraph out = mergeTangentCusps(graph, exactLeaving, kEdgeSize, 1, 0.25, &cusps);

  ASSERT_EQ(cusps.size(), 1u);
  EXPECT_EQ(cusps[0].trimmed_edge, 1) << "the parabola is the shorter curve";
  EXPECT_EQ(cusps[0].kept_edge, 0);
  EXPECT_EQ(cusps[0].vertex, (Point3{0, 0, 0}));
  // The parabola's samples at x = 0 and 2 are 0 and 0.2 off the line (under 0.5, a quarter of
  // the edge size); the one at x = 4 is 0.8 off: it parts there, from the line's sample at 2.
  EXPECT_EQ(cusps[0].parting_point, (Point3{2, 0, 0}));
  EXPECT_NEAR(cusps[0].width, 0.8, 1e-12);
  EXPECT_NEAR(cusps[0].merged_length, distance(Point3{0, 0, 0}, Point3{2, 0.2, 0}), 1e-12);

  // The line is split at the parting point; the parabola starts there and keeps its samples
  // from x = 4 on; the vertex is the end of the line's first piece only.
  ASSERT_EQ(out.polylines.size(), 3u);
  EXPECT_EQ(endsAt(out, Point3{2, 0, 0}), 3);
  EXPECT_EQ(endsAt(out, Point3{0, 0, 0}), 1);
  const FeaturePolyline* parabola = nullptr;
  for (const FeaturePolyline& pl : out.polylines)
    if (pl.edge == 1) parabola = &pl;
  ASSERT_NE(parabola, nullptr);
  ASSERT_EQ(parabola->points.size(), 4u);
  EXPECT_EQ(parabola->points[0], (Point3{2, 0, 0}));
  EXPECT_EQ(parabola->points[1], (Point3{4, 0.8, 0}));
  EXPECT_EQ(parabola->points[3], (Point3{8, 3.2, 0}));
  // Every sample the parabola lost lies within a quarter of the edge size of the line's chain.
  for (const Point3& p : graph.polylines[1].points)
    if (p[0] < 3) EXPECT_LT(nearestOnPolyline(graph.polylines[0].points, p).distance, 0.5);
  // The two now leave their shared end at over 10 degrees (atan(0.8 / 2) = 21.8).
  const Point3 along = parabola->points[1] - parabola->points[0];
  EXPECT_NEAR(std::atan2(along[1], along[0]) * 180 / M_PI, 21.8, 0.05);
  // The line lost nothing; curve ids are 0, 1, 2 in polyline order.
  size_t linePoints = 0;
  for (size_t i = 0; i < out.polylines.size(); ++i) {
    EXPECT_EQ(out.polylines[i].curve, static_cast<int>(i));
    if (out.polylines[i].edge == 0) linePoints += out.polylines[i].points.size();
  }
  EXPECT_EQ(linePoints, graph.polylines[0].points.size() + 1) << "the split point is in both pieces";
}

TEST(TangentCusps, WhichCurveIsTrimmedDoesNotDependOnTheirOrder) {
  FeatureGraph forward, backward;
  forward.polylines = {sampled(range(0, 10, 2), 0, 0), sampled(range(0, 8, 2), kCurvature, 1)};
  backward.polylines = {forward.polylines[1], forward.polylines[0]};
  // The parabola reversed: its cusp end is its back.
  std::reverse(backward.polylines[0].points.begin(), backward.polylines[0].points.end());
  std::vector<TangentCusp> a, b;
  mergeTangentCusps(forward, exactLeaving, kEdgeSize, 1, 0.25, &a);
  const FeatureGraph out = mergeTangentCusps(backward, exactLeaving, kEdgeSize, 1, 0.25, &b);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].trimmed_edge, 1);
  EXPECT_EQ(b[0].parting_point, a[0].parting_point);
  EXPECT_EQ(out.polylines[0].points.back(), (Point3{2, 0, 0})) << "the reversed parabola ends at the parting point";
}

TEST(TangentCusps, CurvesMeetingAtAnAngleOrContinuingEachOtherAreLeftAsTheyAre) {
  // The line continued through the vertex (180 degrees) and a line leaving at 5 degrees.
  FeaturePolyline back = sampled(range(-10, 0, 2), 0, 0);
  FeaturePolyline ahead = sampled(range(0, 10, 2), 0, 2);
  FeaturePolyline steep;
  for (double x : range(0, 8, 2)) steep.points.push_back({x, x * std::tan(5 * M_PI / 180), 0});
  steep.edge = 3;
  FeatureGraph graph;
  graph.polylines = {back, ahead, steep};
  std::vector<TangentCusp> cusps;
  const FeatureGraph out = mergeTangentCusps(
      graph, [](const FeaturePolyline& pl, bool atBack) {
        const Point3 d = atBack ? pl.points[pl.points.size() - 2] - pl.points.back() : pl.points[1] - pl.points[0];
        return (1 / norm(d)) * d;
      },
      kEdgeSize, 1, 0.25, &cusps);
  EXPECT_TRUE(cusps.empty());
  ASSERT_EQ(out.polylines.size(), 3u);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(out.polylines[i].points, graph.polylines[i].points);
}

TEST(TangentCusps, AUserPolylineIsKeptWholeAndTheCurveTangentToItGivesWay) {
  // The line is the user's (and the longer one): the parabola gives way as before. The
  // parabola the user's: the line gives way, from the parabola's chain.
  FeatureGraph graph;
  graph.polylines = {sampled(range(0, 10, 2), 0, 0), sampled(range(0, 8, 2), kCurvature, 1)};
  graph.polylines[0].user = 0;
  std::vector<TangentCusp> cusps;
  mergeTangentCusps(graph, exactLeaving, kEdgeSize, 1, 0.25, &cusps);
  ASSERT_EQ(cusps.size(), 1u);
  EXPECT_EQ(cusps[0].trimmed_edge, 1);

  graph.polylines[0].user = -1;
  graph.polylines[1].user = 0;
  cusps.clear();
  const FeatureGraph out = mergeTangentCusps(graph, exactLeaving, kEdgeSize, 1, 0.25, &cusps);
  ASSERT_EQ(cusps.size(), 1u);
  EXPECT_EQ(cusps[0].trimmed_edge, 0);
  // The line's samples at x = 0 and 2 are within 0.5 of the parabola's chain, the one at 4 is
  // 0.77 off it: the line now starts at the parabola's sample (2, 0.2).
  EXPECT_EQ(cusps[0].parting_point, (Point3{2, 0.2, 0}));
  EXPECT_EQ(cusps[0].resumes_at, (Point3{4, 0, 0}));
  // The user's polyline keeps every point, in two pieces split at the parting point.
  size_t userPoints = 0, userPieces = 0;
  for (const FeaturePolyline& pl : out.polylines)
    if (pl.user >= 0) {
      ++userPieces;
      userPoints += pl.points.size();
    }
  EXPECT_EQ(userPieces, 2u);
  EXPECT_EQ(userPoints, graph.polylines[1].points.size() + 1);

  graph.polylines[0].user = 1;
  cusps.clear();
  mergeTangentCusps(graph, exactLeaving, kEdgeSize, 1, 0.25, &cusps);
  EXPECT_TRUE(cusps.empty()) << "two user polylines are both kept";
}

TEST(TangentCusps, WhenTheShorterCurveNeverPartsTheLongerOneGivesWay) {
  // A parabola so flat it stays within a quarter of the edge size of the line all along (0.064
  // at its end, x = 8): the parabola is kept whole and the line gives way, from the parabola's
  // end, since its own sample at x = 10 is 2 off the parabola's chain.
  FeatureGraph graph;
  graph.polylines = {sampled(range(0, 10, 2), 0, 0), sampled(range(0, 8, 2), 0.001, 1)};
  std::vector<TangentCusp> cusps;
  const FeatureGraph out = mergeTangentCusps(
      graph, [](const FeaturePolyline& pl, bool) { return pl.points[1] - pl.points[0]; }, kEdgeSize, 1, 0.25, &cusps);
  ASSERT_EQ(cusps.size(), 1u);
  EXPECT_EQ(cusps[0].trimmed_edge, 0);
  EXPECT_EQ(cusps[0].parting_point, (Point3{8, 0.064, 0}));
  EXPECT_EQ(cusps[0].resumes_at, (Point3{10, 0, 0}));
  ASSERT_EQ(out.polylines.size(), 2u);
  EXPECT_EQ(out.polylines[0].points, (std::vector<Point3>{{8, 0.064, 0}, {10, 0, 0}}));
  EXPECT_EQ(out.polylines[1].points, graph.polylines[1].points);
}

TEST(TangentCusps, TwoCurvesThatNeverPartAreKeptWhole) {
  // Both within a quarter of the edge size of each other all along: taking either out would
  // drop a sharp edge, so the pair stays as it is.
  FeatureGraph graph;
  graph.polylines = {sampled(range(0, 8, 2), 0, 0), sampled(range(0, 8, 2), 0.001, 1)};
  std::vector<TangentCusp> cusps;
  const FeatureGraph out = mergeTangentCusps(
      graph, [](const FeaturePolyline& pl, bool) { return pl.points[1] - pl.points[0]; }, kEdgeSize, 1, 0.25, &cusps);
  EXPECT_TRUE(cusps.empty());
  ASSERT_EQ(out.polylines.size(), 2u);
  EXPECT_EQ(out.polylines[0].points, graph.polylines[0].points);
  EXPECT_EQ(out.polylines[1].points, graph.polylines[1].points);
}

}  // namespace
}  // namespace oraclemesh
