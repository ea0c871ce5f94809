// Rule Set Q preparation (thesis §3.2, §3.2.1) on small hand-made feature graphs: splitting at
// crossings, star vertices, and Q1's equal incident segments at l_min / 3.
#include <BRepPrimAPI_MakeBox.hxx>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <map>

#include "domain/BrepSolid.h"
#include "features/BrepSharpEdges.h"
#include "features/RuleSetQ.h"
#include "features/UserPolylines.h"

namespace oraclemesh {
namespace {

FeaturePolyline cadCurve(std::vector<Point3> points, int edge) {
  FeaturePolyline pl;
  pl.points = std::move(points);
  pl.source = 0;
  pl.edge = edge;
  return pl;
}

// The length of the end segment of `pl` at `end` (front or back).
double endSegmentAt(const FeaturePolyline& pl, const Point3& end) {
  const auto& p = pl.points;
  return p.front() == end ? distance(p[0], p[1]) : distance(p[p.size() - 1], p[p.size() - 2]);
}

// The point next to `end` on `pl`.
Point3 neighbourOf(const FeaturePolyline& pl, const Point3& end) {
  const auto& p = pl.points;
  return p.front() == end ? p[1] : p[p.size() - 2];
}

void expectNear(const Point3& a, const Point3& b, double tolerance) {
  EXPECT_LE(distance(a, b), tolerance) << "(" << a[0] << ", " << a[1] << ", " << a[2] << ") vs (" << b[0] << ", "
                                       << b[1] << ", " << b[2] << ")";
}

TEST(RuleSetQ, CadCurvesCrossingMidSegmentShareTheCrossing) {
  // Two sharp edges of different parts on a common plane, crossing inside a segment of each.
  FeatureGraph graph;
  graph.polylines = {cadCurve({{0, 0, 0}, {4, 0, 0}, {10, 0, 0}}, 1), cadCurve({{3, -5, 0}, {3, 5, 0}}, 2)};
  const FeatureGraph split = splitAtCrossings(graph, 1e-9, 1e-6, 1);
  ASSERT_EQ(split.polylines.size(), 4u);
  int atCrossing = 0;
  for (const FeaturePolyline& pl : split.polylines)
    for (const Point3& p : {pl.points.front(), pl.points.back()}) atCrossing += p == Point3{3, 0, 0};
  EXPECT_EQ(atCrossing, 4);
  // Without a curve tolerance (the old behaviour) CAD pairs are left alone.
  EXPECT_EQ(splitAtCrossings(graph, 1e-9).polylines.size(), 2u);
}

TEST(RuleSetQ, ACrossingNextToAnInnerSampleTakesItsPlace) {
  // A curve sampled every 1 crossed at x = 2.1 (next to its sample at 2), at x = 5.5 (halfway
  // between two) and at x = 9.8 (next to its end): the sample at 2 becomes the crossing instead
  // of leaving a 0.1 piece beside it, 5.5 is added, and the end at 10 stays where it is (other
  // curves share it), so a 0.2 piece remains there.
  std::vector<Point3> along;
  for (int k = 0; k <= 10; ++k) along.push_back({double(k), 0, 0});
  FeatureGraph graph;
  graph.polylines = {cadCurve(along, 1), cadCurve({{2.1, -5, 0}, {2.1, 5, 0}}, 2),
                     cadCurve({{5.5, -5, 0}, {5.5, 5, 0}}, 3), cadCurve({{9.8, -5, 0}, {9.8, 5, 0}}, 4)};
  const FeatureGraph split = splitAtCrossings(graph, 1e-9, 1e-6, 1);
  std::vector<Point3> kept;
  for (const FeaturePolyline& pl : split.polylines)
    if (pl.edge == 1) kept.insert(kept.end(), pl.points.begin() + (kept.empty() ? 0 : 1), pl.points.end());
  const std::vector<double> expected = {0, 1, 2.1, 3, 4, 5, 5.5, 6, 7, 8, 9, 9.8, 10};
  ASSERT_EQ(kept.size(), expected.size());
  for (size_t k = 0; k < kept.size(); ++k) expectNear(kept[k], {expected[k], 0, 0}, 1e-12);
  // Every crossing is still a vertex of both curves.
  EXPECT_EQ(findStarVertices(split, 1e-9).size(), 3u);
}

TEST(RuleSetQ, ANearMissBesideACrossingIsTheSameCrossing) {
  // Crossed at x = 2, 0.2 before its sample at 2.2: the chord from 2.2 on passes within the
  // curve tolerance (0.25) of the other curve too. One crossing, at x = 2, where both curves
  // break; no second one 0.1 beside it.
  FeatureGraph graph;
  graph.polylines = {cadCurve({{-2, 0, 0}, {0, 0, 0}, {2.2, 0, 0}, {4, 0, 0}, {6, 0, 0}}, 1),
                     cadCurve({{2, -5, 0}, {2, -2.5, 0}, {2, 0.5, 0}, {2, 3, 0}, {2, 5, 0}}, 2)};
  const FeatureGraph split = splitAtCrossings(graph, 1e-9, 0.25, 1);
  ASSERT_EQ(split.polylines.size(), 4u);
  for (const FeaturePolyline& pl : split.polylines) {
    const Point3 inner = distance(pl.points.front(), {2, 0, 0}) < 1e-12 ? pl.points.front() : pl.points.back();
    expectNear(inner, {2, 0, 0}, 1e-12);
    for (size_t k = 0; k + 1 < pl.points.size(); ++k) EXPECT_GT(distance(pl.points[k], pl.points[k + 1]), 0.5);
  }
}

TEST(RuleSetQ, ChordsOfCurvesThatNeverMeetAreNotSplit) {
  // Two coarse chords cross within the chord tolerance, but the exact curves they sample stay
  // 0.2 apart (Kurbelwelle.stp: arcs on planes 0.2 mm apart); splitting them would put a
  // vertex on neither curve.
  FeatureGraph graph;
  graph.polylines = {cadCurve({{0, 0, 0}, {10, 0, 0}}, 1), cadCurve({{5, -5, 0.1}, {5, 5, 0.1}}, 2)};
  double askedGapOf = 0;
  const ExactCurveGap apart = [&](const FeaturePolyline&, const FeaturePolyline&) {
    ++askedGapOf;
    return 0.2;
  };
  EXPECT_EQ(splitAtCrossings(graph, 0.05, 0.5, 1, apart).polylines.size(), 2u);
  EXPECT_EQ(askedGapOf, 1);  // once per pair, not per segment pair
  // Exact curves that do meet (gap 0), or an unknown gap, keep the chord rule: both are split.
  const ExactCurveGap meeting = [](const FeaturePolyline&, const FeaturePolyline&) { return 0.0; };
  const ExactCurveGap unknown = [](const FeaturePolyline&, const FeaturePolyline&) { return -1.0; };
  EXPECT_EQ(splitAtCrossings(graph, 0.05, 0.5, 1, meeting).polylines.size(), 4u);
  EXPECT_EQ(splitAtCrossings(graph, 0.05, 0.5, 1, unknown).polylines.size(), 4u);
}

TEST(RuleSetQ, ACircleRestingOnALineIsSplitWhereItTouchesIt) {
  // A rod's end circle (radius 3, centre (0, 3)) on the top edge of the plate it rests on (the
  // line y = 0): sampled at 24 chords, the samples next to the touching point lie 0.1 from
  // the line and the chords cross it at a few degrees on both sides of (0, 0). Unsplit, the
  // two curves meet there without a shared vertex and Rule Set T splits both without end.
  // They must meet at the exact touching point, bitwise, and nowhere else.
  const double r = 3;
  std::vector<Point3> circle;
  for (int k = 0; k <= 24; ++k) {
    const double t = M_PI / 2 + 0.1 + 2 * M_PI * k / 24;  // the seam on top, no sample at the touching point
    circle.push_back({r * std::cos(t), r + r * std::sin(t), 0});
  }
  FeatureGraph graph;
  graph.polylines = {cadCurve(circle, 1), cadCurve({{-10, 0, 0}, {-5, 0, 0}, {5, 0, 0}, {10, 0, 0}}, 2)};
  const ExactCurveGap touching = [](const FeaturePolyline&, const FeaturePolyline&) { return 0.0; };
  const ExactCurveProjection project = [&](const FeaturePolyline& curve, const Point3& p) -> std::optional<Point3> {
    if (curve.edge == 2) return Point3{std::clamp(p[0], -10.0, 10.0), 0, 0};
    const Point3 centre{0, r, 0};
    const double d = distance(p, centre);
    if (!(d > 0)) return std::nullopt;
    return centre + (r / d) * (p - centre);
  };
  // Without the exact curves nothing tells the touching from chords passing close.
  EXPECT_EQ(splitAtCrossings(graph, 0.05, 0.3, 1).polylines.size(), 2u);
  const FeatureGraph split = splitAtCrossings(graph, 0.05, 0.3, 1, touching, project);
  ASSERT_EQ(split.polylines.size(), 4u);
  int endsAtTheTouchingPoint = 0;
  for (const FeaturePolyline& pl : split.polylines)
    for (const Point3& end : {pl.points.front(), pl.points.back()})
      if (distance(end, Point3{0, 0, 0}) < 1e-6) ++endsAtTheTouchingPoint;
  EXPECT_EQ(endsAtTheTouchingPoint, 4);
  // The circle's pieces run from the touching point round to their seam, the line's out to its
  // ends: no piece turns back on itself next to the split.
  for (const FeaturePolyline& pl : split.polylines)
    for (size_t k = 0; k + 2 < pl.points.size(); ++k) {
      const Point3 u = pl.points[k + 1] - pl.points[k], v = pl.points[k + 2] - pl.points[k + 1];
      EXPECT_GT(dot(u, v), 0) << "curve " << pl.edge << " turns back at sample " << k + 1;
    }
}

TEST(RuleSetQ, CurvesCrossingNearTheirEndsAreSplitNotTakenForATee) {
  // A box's top edge (y = 10) and the bottom edge (x = 8) of a box standing on it and
  // overhanging by 1: they cross 2 from one end and 1 from the other, closer than the T
  // clearance (100 x the curve tolerance) of the meeting point, yet neither ends on the other.
  FeatureGraph graph;
  graph.polylines = {cadCurve({{0, 10, 10}, {2.5, 10, 10}, {5, 10, 10}, {7.5, 10, 10}, {10, 10, 10}}, 1),
                     cadCurve({{8, 3, 10}, {8, 5, 10}, {8, 7, 10}, {8, 9, 10}, {8, 11, 10}}, 2)};
  const FeatureGraph split = splitAtCrossings(graph, 1e-9, 0.05, 1);
  ASSERT_EQ(split.polylines.size(), 4u);
  int atCrossing = 0;
  for (const FeaturePolyline& pl : split.polylines)
    for (const Point3& p : {pl.points.front(), pl.points.back()}) atCrossing += p == Point3{8, 10, 10};
  EXPECT_EQ(atCrossing, 4);
}

TEST(RuleSetQ, CurvesLeavingACommonVertexAtASmallAngleAreNotSplit) {
  // Two curves from the origin 2 degrees apart, sampled every unit: their chords come within
  // the tolerance of each other near the vertex, which is no crossing.
  FeaturePolyline a, b;
  const double angle = 2 * M_PI / 180;
  for (int k = 0; k <= 10; ++k) {
    a.points.push_back({double(k), 0, 0});
    b.points.push_back({k * std::cos(angle), k * std::sin(angle), 0});
  }
  FeatureGraph graph;
  graph.polylines = {cadCurve(a.points, 1), cadCurve(b.points, 2)};
  EXPECT_EQ(splitAtCrossings(graph, 1e-9, 0.05, 2).polylines.size(), 2u);
}

TEST(RuleSetQ, CurvesAlongTheSameArcAreNotSplit) {
  // Edges of two parts in contact along one arc (presse_asm.step has such pairs), sampled at
  // different points: their chords cross each other all along, which is no crossing.
  auto arc = [](double fromDeg, double toDeg) {
    std::vector<Point3> points;
    for (double deg = fromDeg; deg <= toDeg + 1e-9; deg += 2)
      points.push_back({10 * std::cos(deg * M_PI / 180), 10 * std::sin(deg * M_PI / 180), 0});
    return points;
  };
  FeatureGraph graph;
  graph.polylines = {cadCurve(arc(0, 90), 1), cadCurve(arc(45, 135), 2)};
  // The chords stray 0.0015 from the arc; the tolerance covers twice that, as in the pipeline.
  EXPECT_EQ(splitAtCrossings(graph, 1e-9, 0.004, 1).polylines.size(), 2u);
}

TEST(RuleSetQ, CurvesSampledFinerThanTheSnapKeepTheirEnds) {
  // Sizes from the geometry sample a curve every 0.01 where the snap distance (2.5 % of the
  // job's edge size) is 0.1: the split thins it to that, and used to drop its last vertex with
  // the others, so the star vertex it shares with the next curve was lost (part.step at
  // "moderate": 42 of 46).
  std::vector<Point3> fine, next;
  for (int k = 0; k <= 100; ++k) fine.push_back({0.01 * k, 0, 0});
  for (int k = 0; k <= 4; ++k) next.push_back({1, 0.25 * k, 0});
  FeatureGraph graph;
  graph.polylines = {cadCurve(fine, 1), cadCurve(next, 2)};
  const FeatureGraph split = splitAtCrossings(graph, 0.1, 1e-6, 1);
  ASSERT_EQ(split.polylines.size(), 2u);
  const std::vector<Point3>& thinned = split.polylines[0].points;
  EXPECT_EQ(thinned.front(), fine.front());
  EXPECT_EQ(thinned.back(), fine.back());
  EXPECT_LT(thinned.size(), fine.size());
  for (size_t k = 0; k + 1 < thinned.size(); ++k) EXPECT_GT(distance(thinned[k], thinned[k + 1]), 0.1 - 1e-12);
  EXPECT_EQ(split.polylines[1].points, next);
  EXPECT_EQ(findStarVertices(split, 1e-9).size(), 1u);
}

TEST(RuleSetQ, TJunctionIsSplitAndEqualized) {
  // A curve ending inside a segment of another: the other is split there, giving a star
  // vertex of three curves with end segments 1, 1 and 2 long.
  FeatureGraph graph;
  graph.polylines = {cadCurve({{0, 0, 0}, {2, 0, 0}, {4, 0, 0}, {6, 0, 0}, {8, 0, 0}, {10, 0, 0}}, 1),
                     cadCurve({{5, 0, 0}, {5, 2, 0}, {5, 4, 0}, {5, 6, 0}}, 2)};
  const FeatureGraph split = splitAtCrossings(graph, 1e-9, 1e-6, 1);
  ASSERT_EQ(split.polylines.size(), 3u);
  const Point3 star{5, 0, 0};
  const std::vector<StarVertex> stars = findStarVertices(split, 1e-9);
  ASSERT_EQ(stars.size(), 1u);
  EXPECT_EQ(stars[0].point, star);
  EXPECT_EQ(stars[0].incident.size(), 3u);
  EXPECT_DOUBLE_EQ(stars[0].shortest_incident_length, 1);

  const FeatureGraph equal = equalizeStarSegments(split, stars);
  ASSERT_EQ(equal.polylines.size(), 3u);
  std::vector<Point3> inserted;
  for (size_t i = 0; i < equal.polylines.size(); ++i) {
    const FeaturePolyline& pl = equal.polylines[i];
    EXPECT_EQ(pl.points.size(), split.polylines[i].points.size() + 1) << "one point per incident end";
    EXPECT_NEAR(endSegmentAt(pl, star), 1.0 / 3, 1e-12);
    inserted.push_back(neighbourOf(pl, star));
    // The far ends are ordinary ends: untouched.
    const Point3 far = pl.points.front() == star ? pl.points.back() : pl.points.front();
    EXPECT_EQ(endSegmentAt(pl, far), endSegmentAt(split.polylines[i], far));
  }
  std::sort(inserted.begin(), inserted.end());
  expectNear(inserted[0], {5 - 1.0 / 3, 0, 0}, 1e-12);
  expectNear(inserted[1], {5, 1.0 / 3, 0}, 1e-12);
  expectNear(inserted[2], {5 + 1.0 / 3, 0, 0}, 1e-12);

  // Now free: a second pass changes nothing.
  const FeatureGraph again = equalizeStarSegments(equal, findStarVertices(equal, 1e-9));
  for (size_t i = 0; i < equal.polylines.size(); ++i) EXPECT_EQ(again.polylines[i].points, equal.polylines[i].points);
}

TEST(RuleSetQ, BoxCornersGetEqualIncidentSegments) {
  // A 10 x 20 x 30 box with 4 mm segments: edges of 10 (3 segments), 20 (5) and 30 (8) meet
  // at every corner, so l_min = 10 / 3 and each edge gets a point 10 / 9 from each corner.
  BrepSolid solid(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "box");
  const FeatureGraph graph = extractSharpEdges(solid, 0, 30, 4);
  const std::vector<StarVertex> stars = findStarVertices(graph, 1e-9);
  ASSERT_EQ(stars.size(), 8u);
  for (const StarVertex& s : stars) {
    EXPECT_EQ(s.incident.size(), 3u);
    EXPECT_NEAR(s.shortest_incident_length, 10.0 / 3, 1e-9);
  }
  const FeatureGraph equal = equalizeStarSegments(graph, stars);
  for (size_t i = 0; i < equal.polylines.size(); ++i)
    EXPECT_EQ(equal.polylines[i].points.size(), graph.polylines[i].points.size() + 2);
  const double third = 10.0 / 9;
  for (const StarVertex& s : stars) {
    std::vector<Point3> around;
    for (const StarVertex::Incident& e : s.incident) {
      const FeaturePolyline& pl = equal.polylines[e.polyline];
      EXPECT_NEAR(endSegmentAt(pl, s.point), third, 1e-9);
      around.push_back(neighbourOf(pl, s.point));
    }
    // One point along each axis from the corner, towards the box.
    for (int axis = 0; axis < 3; ++axis) {
      Point3 expected = s.point;
      expected[axis] += s.point[axis] == 0 ? third : -third;
      double nearest = 1e9;
      for (const Point3& p : around) nearest = std::min(nearest, distance(p, expected));
      EXPECT_LT(nearest, 1e-9) << "corner (" << s.point[0] << ", " << s.point[1] << ", " << s.point[2] << ") axis "
                               << axis;
    }
  }
}

TEST(RuleSetQ, ClosedCircleThroughItsVertex) {
  // A closed polyline (a full circle of radius 5 with its B-rep vertex at angle 0) whose
  // first and last segments differ (30 and 60 degrees): its vertex is a star vertex of the
  // circle alone; both ends get a point at l_min / 3 along their segment.
  FeaturePolyline circle;
  for (double deg : {0.0, 30.0, 90.0, 180.0, 300.0, 360.0}) {
    const double a = deg * M_PI / 180;
    circle.points.push_back(deg == 360 ? Point3{5, 0, 0} : Point3{5 * std::cos(a), 5 * std::sin(a), 0});
  }
  circle.source = 0;
  circle.edge = 0;
  FeatureGraph graph;
  graph.polylines = {circle};
  const std::vector<StarVertex> stars = findStarVertices(graph, 1e-9);
  ASSERT_EQ(stars.size(), 1u);
  ASSERT_EQ(stars[0].incident.size(), 2u);
  const double shortChord = 2 * 5 * std::sin(15 * M_PI / 180), longChord = 2 * 5 * std::sin(30 * M_PI / 180);
  EXPECT_NEAR(stars[0].shortest_incident_length, shortChord, 1e-12);
  const FeatureGraph equal = equalizeStarSegments(graph, stars);
  const std::vector<Point3>& p = equal.polylines[0].points;
  ASSERT_EQ(p.size(), circle.points.size() + 2);
  EXPECT_EQ(p.front(), p.back()) << "still closed";
  EXPECT_NEAR(distance(p[0], p[1]), shortChord / 3, 1e-12);
  EXPECT_NEAR(distance(p[p.size() - 1], p[p.size() - 2]), shortChord / 3, 1e-12);
  // On the original chords: a third of the 30-degree chord, a sixth of the 60-degree one.
  expectNear(p[1], circle.points[0] + (1.0 / 3) * (circle.points[1] - circle.points[0]), 1e-12);
  expectNear(p[p.size() - 2], circle.points[5] + (shortChord / 3 / longChord) * (circle.points[4] - circle.points[5]),
             1e-12);

  // A uniformly sampled circle is free already: nothing to insert.
  FeaturePolyline uniform;
  for (int k = 0; k <= 12; ++k) {
    const double a = k * M_PI / 6;
    uniform.points.push_back(k == 12 ? Point3{5, 0, 0} : Point3{5 * std::cos(a), 5 * std::sin(a), 0});
  }
  FeatureGraph round;
  round.polylines = {uniform};
  EXPECT_EQ(equalizeStarSegments(round, findStarVertices(round, 1e-9)).polylines[0].points, uniform.points);
}

}  // namespace
}  // namespace oraclemesh
