// The refiner's insertion core, T1, the hook the planar-face layer uses, and the whole of
// meshWithRuleSetT on a small oracle (a sphere with a constrained segment or circle).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <set>
#include <utility>

#include "Error.h"
#include "domain/Sphere.h"
#include "mesh/Quality.h"
#include "refine/Circumcentre.h"
#include "refine/RuleSetTRefiner.h"
#include "sizing/SizeField.h"

namespace oraclemesh::refine {
namespace {

HierarchicalOracle unitBall() { return HierarchicalOracle({{std::make_shared<Sphere>(Point3{0, 0, 0}, 1, "ball"), Role::Material, 1}}); }

RuleSetTOptions options(double size, double ratio = 2) {
  RuleSetTOptions o;
  o.criteria.defaults.cell_size = size;
  o.criteria.defaults.facet_size = size;
  o.criteria.defaults.facet_distance = 0.05;
  o.criteria.defaults.cell_radius_edge_ratio = ratio;
  return o;
}

// One straight constrained segment inside the ball, from (-0.5, 0, 0) to (0.5, 0, 0): its
// diametral ball is the ball of radius 0.5 about the origin.
FeatureGraph diameterSegment() {
  FeatureGraph g;
  FeaturePolyline pl;
  pl.points = {{-0.5, 0, 0}, {0.5, 0, 0}};
  pl.curve = 7;
  g.polylines.push_back(pl);
  return g;
}

struct Refiner {
  HierarchicalOracle oracle = unitBall();
  FeatureGraph features = diameterSegment();
  RuleSetTOptions opts = options(0.5);
  RunControl control;
  RuleSetTStatistics stats;
  RuleSetTRefiner refiner{oracle, features, opts, control, stats};

  CH anyCell() const { return refiner.triangulation().finite_cells_begin(); }
  size_t vertices() const { return refiner.triangulation().number_of_vertices(); }
};

bool finitePoint(const CgalPoint& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

// The presse nut's refinement (PresseNutThesis) once sent a NaN circumcentre's dual edge to
// the oracle: these are the cases where the floating-point circumcentre is not finite.
TEST(RefineCircumcentre, FiniteWhereTheFloatingPointFormulaFails) {
  // A regular cell at 1e155: the squared lengths overflow in doubles, not in rationals.
  const double s = 1e155;
  const CgalPoint a(0, 0, 0), b(s, 0, 0), c(0, s, 0), d(0, 0, s);
  ASSERT_FALSE(finitePoint(CGAL::circumcenter(a, b, c, d)));
  const CgalPoint big = finiteCircumcentre(a, b, c, d, 1);
  ASSERT_TRUE(finitePoint(big));
  EXPECT_NEAR(big.x() / s, 0.5, 1e-15);
  EXPECT_NEAR(big.y() / s, 0.5, 1e-15);
  EXPECT_NEAR(big.z() / s, 0.5, 1e-15);

  // A cell flat but for a denormal height: its centre is beyond the range of doubles, below
  // the plane of a, b, c (the corner d lies inside the circle through them, above it).
  const CgalPoint f(0, 0, 0), g(1, 0, 0), h(0, 1, 0), k(0.3, 0.4, 5e-324);
  ASSERT_FALSE(finitePoint(CGAL::circumcenter(f, g, h, k)));
  const CgalPoint far = finiteCircumcentre(f, g, h, k, 40);
  ASSERT_TRUE(finitePoint(far));
  EXPECT_NEAR(far.z(), -40, 1e-9);
  EXPECT_NEAR(std::hypot(far.x(), far.y()), 0, 1e-9);

  // Exactly flat (no sphere): the far point lies on the normal of the plane.
  const CgalPoint flat = finiteCircumcentre(f, g, h, CgalPoint(0.3, 0.4, 0), 40);
  ASSERT_TRUE(finitePoint(flat));
  EXPECT_NEAR(std::abs(flat.z()), 40, 1e-9);

  // Where the formula works, its answer unchanged (the meshes do not depend on the fallback).
  const CgalPoint e(0.1, 0.2, 0.3);
  EXPECT_EQ(finiteCircumcentre(g, h, k, e, 40), CGAL::circumcenter(g, h, k, e));
}

TEST(RefineCircumcentre, NonFinitePointsAreOutsideAndCrossNothing) {
  const HierarchicalOracle ball = unitBall();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(ball.bbox().contains({nan, 0, 0}));
  EXPECT_EQ(ball.label({0, nan, 0}), 0);
  EXPECT_EQ(ball.label({0, 0, 0}), 1);
  EXPECT_THROW(ball.crossings({0, 0, 0}, {inf, 0, 0}), Error);
  EXPECT_THROW(ball.crossings({nan, 0, 0}, {0, 0, 0}), Error);
  EXPECT_EQ(ball.crossings({0, 0, 0}, {2, 0, 0}).size(), 1u);
}

// The criteria skip the field queries at circumcentres and ball centres that a lower bound
// from the corners' values already decides; the bound must never exceed the field.
TEST(RefineSizeBounds, CornerBoundsStayUnderTheFieldsAndDecideMostCells) {
  const HierarchicalOracle oracle = unitBall();
  const FeatureGraph features = diameterSegment();
  RuleSetTOptions opts = options(0.5);
  MaterialCriteria::FromField& fromField = opts.criteria.defaults.from_field;
  fromField.cell_size = fromField.facet_size = fromField.facet_distance = true;
  opts.criteria.field = std::make_shared<SizeField>(
      std::vector<SizeSample>{{{0.5, 0, 0}, 0.08, SizeReason::Curvature}, {{-0.3, 0.4, 0}, 0.15, SizeReason::ShortEdge}},
      0.3, 0.5, 1e-3);
  // The cells' own field (the job's has larger sizes; the same samples keep this mesh fine).
  opts.criteria.cell_field = opts.criteria.field;
  opts.criteria.gap_field =
      std::make_shared<SizeField>(std::vector<SizeSample>{{{0, 0, 0.9}, 0.1, SizeReason::Gap}}, 0.5, 1.0, 1e-3);
  RunControl control;
  RuleSetTStatistics stats;
  RuleSetTRefiner refiner(oracle, features, opts, control, stats);
  const TetMesh mesh = refiner.run();
  ASSERT_GT(mesh.tets.size(), 1000u);
  int64_t labelled = 0, decided = 0;
  const Delaunay& dt = refiner.triangulation();
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    const VH corners[4] = {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
    const Point3 centre = c->info().circumcentre;
    const CriteriaTable::FieldValues below = refiner.fieldsBelow(centre, corners, 4);
    const CriteriaTable::FieldValues exact = opts.criteria.fieldsAt(centre);
    EXPECT_LE(below.field, exact.field);
    EXPECT_LE(below.gap, exact.gap);
    EXPECT_LE(below.cell, opts.criteria.cell_field->at(centre));
    if (c->info().label <= 0) continue;
    ++labelled;
    decided += c->info().radius <= std::min(opts.criteria.defaults.cell_size, below.cell);
  }
  std::cout << "[ figures  ] " << decided << " of " << labelled << " cells meet their size by the corner bound\n";
  EXPECT_GT(decided, labelled / 2);
  EXPECT_EQ(stats.elements_left_total, 0);
}

TEST(RefineInsertionCore, RefusesAPointThatEncroachesASubsegment) {
  Refiner r;
  r.refiner.insertInitialPoints();
  ASSERT_EQ(r.refiner.segments().size(), 1u);
  const size_t before = r.vertices();
  // Inside the segment's diametral ball: found encroaching on the conflict zone, not inserted.
  const Zone zone = r.refiner.examine({0.1, 0.2, 0}, r.anyCell());
  EXPECT_EQ(zone.encroached, 0);
  EXPECT_FALSE(r.refiner.isFree(zone));
  EXPECT_EQ(r.refiner.insertIfFree({0.1, 0.2, 0}, r.anyCell(), 3, -1), VH());
  EXPECT_EQ(r.vertices(), before);
  // The segment splitting itself does not count as encroached.
  EXPECT_EQ(r.refiner.examine({0, 0, 0}, r.anyCell(), 0).encroached, -1);
  // Just outside the ball: it goes in.
  const VH v = r.refiner.insertIfFree({0.1, 0.6, 0}, r.anyCell(), 3, -1);
  ASSERT_NE(v, VH());
  EXPECT_EQ(r.vertices(), before + 1);
  EXPECT_EQ(v->info().dimension, 3);
  // An existing vertex is a duplicate.
  EXPECT_TRUE(r.refiner.examine({0.1, 0.6, 0}, r.anyCell()).duplicate);
  EXPECT_EQ(r.refiner.insertIfFree({0.1, 0.6, 0}, r.anyCell(), 3, -1), VH());
}

TEST(RefineConstrainedSegments, T1SplitsAnEncroachedSubsegmentAtItsMidpoint) {
  Refiner r;
  r.refiner.insertInitialPoints();
  EXPECT_FALSE(r.refiner.refineOneSegment()) << "the lone segment is not encroached at first";
  // Put a vertex into its diametral ball past the insertion core's check.
  r.refiner.commit(r.refiner.examine({0.1, 0.3, 0}, r.anyCell()), 3, -1);
  ASSERT_TRUE(r.refiner.refineOneSegment());
  EXPECT_EQ(r.stats.insertions.at("T1.2"), 1);
  const std::vector<Subsegment>& s = r.refiner.segments();
  ASSERT_EQ(s.size(), 3u);
  EXPECT_FALSE(s[0].alive);
  ASSERT_TRUE(s[1].alive && s[2].alive);
  EXPECT_EQ(s[1].b, s[2].a);
  EXPECT_EQ(toPoint3(s[1].b->point()), (Point3{0, 0, 0}));
  EXPECT_EQ(s[1].b->info().dimension, 1);
  EXPECT_EQ(s[1].b->info().curve, 7);
  // The halves are Delaunay edges and the vertex (0.1, 0.3, 0) encroaches neither.
  for (int k : {1, 2}) {
    CH c;
    int i, j;
    EXPECT_TRUE(r.refiner.triangulation().is_edge(s[k].a, s[k].b, c, i, j));
  }
  EXPECT_FALSE(r.refiner.refineOneSegment());
}

// A hook that pins every vertex and counts the core's calls.
struct CountingHook : RefinementHook {
  int added = 0, emptied = 0, done = 0;
  void vertexAdded(VH) override { ++added; }
  bool labelsByBarycentre(CH) const override { return false; }
  bool hasUndefinedCircumsphere(CH) const override { return false; }
  bool refineOne() override { return false; }
  bool queuesEmptied() override { return ++emptied, false; }
  void refinementDone() override { ++done; }
  const char* checkPhase() const override { return "counting_check"; }
  bool pinsVertex(VH) const override { return true; }
};

TEST(RefineHook, CoreCallsTheHookAtItsFixedPoints) {
  // A high sliver target, so that rule P has vertices to move when nothing pins them.
  Refiner unpinned;
  unpinned.opts.sliver_dihedral_deg = 30;
  unpinned.refiner.run();
  ASSERT_GT(unpinned.stats.vertex_moves, 0);

  Refiner r;
  r.opts.sliver_dihedral_deg = 30;
  CountingHook hook;
  r.refiner.setHook(&hook);
  const TetMesh mesh = r.refiner.run();
  ASSERT_FALSE(mesh.tets.empty());
  EXPECT_EQ(static_cast<size_t>(hook.added), r.vertices()) << "every vertex, bounding corners too";
  EXPECT_GE(hook.emptied, 1);
  EXPECT_EQ(hook.done, 1);
  EXPECT_TRUE(r.stats.seconds.count("counting_check"));
  EXPECT_EQ(r.stats.vertex_moves, 0) << "rule P moved a vertex the hook pins";
}

double circumradius(const TetMesh& m, size_t t) {
  const auto& v = m.tets[t];
  const Point3 a = m.points[v[0]], b = m.points[v[1]] - a, c = m.points[v[2]] - a, d = m.points[v[3]] - a;
  const Point3 num = dot(b, b) * cross(c, d) + dot(c, c) * cross(d, b) + dot(d, d) * cross(b, c);
  return norm(num) / (2 * std::abs(dot(b, cross(c, d))));
}

double shortestEdge(const TetMesh& m, size_t t) {
  double shortest = 1e300;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) shortest = std::min(shortest, distance(m.points[m.tets[t][i]], m.points[m.tets[t][j]]));
  return shortest;
}

TEST(RefineMeshWithRuleSetT, SphereWithEquatorMeetsCriteriaAndKeepsTheCircle) {
  const HierarchicalOracle oracle = unitBall();
  FeatureGraph features;
  FeaturePolyline equator;
  constexpr int kSamples = 24;
  for (int k = 0; k <= kSamples; ++k) {
    const double t = 2 * M_PI * (k % kSamples) / kSamples;
    equator.points.push_back({std::cos(t), std::sin(t), 0});
  }
  equator.curve = 3;
  features.polylines.push_back(equator);
  const double size = 0.35, ratio = 2;
  RuleSetTStatistics stats;
  const TetMesh m = meshWithRuleSetT(oracle, features, options(size, ratio), RunControl(), &stats);
  ASSERT_GT(m.tets.size(), 100u);
  EXPECT_EQ(stats.elements_left_total, 0);
  EXPECT_EQ(stats.subsegments_not_edges, 0);
  EXPECT_EQ(stats.encroached_subsegments, 0);
  EXPECT_EQ(stats.restricted_facets_off_boundary, 0);
  EXPECT_GT(stats.insertions.at("T2.2"), 0);
  // T3's criteria hold for every tet.
  for (size_t t = 0; t < m.tets.size(); ++t) {
    const double r = circumradius(m, t);
    EXPECT_LE(r, size * (1 + 1e-6)) << "tet " << t;
    EXPECT_LE(r / shortestEdge(m, t), ratio * (1 + 1e-6)) << "tet " << t;
  }
  // The circle is there: its polyline points are mesh vertices, and its feature edges are tet
  // edges on its chords whose lengths add up to the polygon's perimeter.
  std::set<std::pair<int64_t, int64_t>> edges;
  for (const auto& t : m.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) edges.insert(std::minmax(t[i], t[j]));
  for (const Point3& p : equator.points) {
    double nearest = 1e300;
    for (const Point3& q : m.points) nearest = std::min(nearest, distance(p, q));
    EXPECT_LT(nearest, 1e-12) << "polyline point not a mesh vertex";
  }
  double perimeter = 0, chords = 0;
  for (size_t k = 0; k + 1 < equator.points.size(); ++k) perimeter += distance(equator.points[k], equator.points[k + 1]);
  ASSERT_GE(m.feature_edges.size(), static_cast<size_t>(kSamples));
  for (size_t e = 0; e < m.feature_edges.size(); ++e) {
    const auto [a, b] = m.feature_edges[e];
    EXPECT_TRUE(edges.count(std::minmax(a, b))) << "feature edge " << e << " is no tet edge";
    EXPECT_EQ(m.feature_edge_curves[e], 3);
    double offChord = 1e300;
    for (size_t k = 0; k + 1 < equator.points.size(); ++k)
      offChord = std::min(offChord, distanceToSegment(m.points[a], equator.points[k], equator.points[k + 1]) +
                                        distanceToSegment(m.points[b], equator.points[k], equator.points[k + 1]));
    EXPECT_LT(offChord, 1e-12) << "feature edge " << e << " is off the polyline";
    chords += distance(m.points[a], m.points[b]);
  }
  EXPECT_NEAR(chords, perimeter, 1e-9);
}

}  // namespace
}  // namespace oraclemesh::refine
