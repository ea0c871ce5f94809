// The operations of src/core/improve on hand-built configurations. Flips: three points a, b, c
// on the unit circle in z = 0 and two apexes d = (0,0,h), e = (0,0,-h). At h = 0.2 the two
// tets abcd, abce are flat (21.8 degrees) and the three around de are better (43.6); at h = 1
// the three around de (39.2) are worse than the two (63.4). Edge removal: five or six points on
// the unit circle around the axis de. Multi-face removal: a pentagon fanned between two
// apexes. Smoothing and edge collapse: a fan over a planar boundary patch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "RunControl.h"
#include "improve/BoundaryPlacement.h"
#include "improve/EdgeCollapse.h"
#include "improve/EdgeRemoval.h"
#include "improve/FaceRemoval.h"
#include "improve/ImprovementMesh.h"
#include "improve/MeshImprovement.h"
#include "improve/Smoothing.h"
#include "improve/VertexInsertion.h"
#include "improve/TetShape.h"
#include "mesh/Quality.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"

namespace oraclemesh {
namespace {

constexpr int64_t A = 0, B = 1, C = 2, D = 3, E = 4;

void orientAll(TetMesh& m) {
  for (auto& t : m.tets)
    if (test::orientation(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) < 0) std::swap(t[0], t[1]);
}

// Apexes at (0, 0, h) and (0, 0, -h), then ring points (angle around the axis, distance from
// it, height) in counter-clockwise order; tets around the axis. The boundary is every tet face
// without the axis, of material 1 against the outside.
struct RingPoint {
  double angle, radius, z;
};

TetMesh ringAroundAxis(double h, const std::vector<RingPoint>& ring) {
  TetMesh m;
  m.points = {{0, 0, h}, {0, 0, -h}};
  for (const RingPoint& r : ring) m.points.push_back({r.radius * std::cos(r.angle), r.radius * std::sin(r.angle), r.z});
  const int64_t n = static_cast<int64_t>(ring.size());
  for (int64_t i = 0; i < n; ++i) {
    const int64_t r = 2 + i, s = 2 + (i + 1) % n;
    m.tets.push_back({0, 1, r, s});
    m.tet_materials.push_back(1);
    m.boundary.push_back({{0, r, s}, 1, 0});
    m.boundary.push_back({{1, r, s}, 1, 0});
  }
  orientAll(m);
  m.vertex_dimension.assign(m.points.size(), 2);
  m.vertex_curve.assign(m.points.size(), -1);
  return m;
}

// Regular rings of n around an axis of 2h.
TetMesh ringAroundAxis(int n, double h) {
  std::vector<RingPoint> ring;
  for (int i = 0; i < n; ++i) ring.push_back({2 * M_PI * i / n, 1, 0});
  return ringAroundAxis(h, ring);
}

// Rings (found by a random search) with a sliver around the axis that edge removal lifts:
// five points, 4.2 -> 40.7 degrees; four points, 4.0 -> 47.9 degrees.
TetMesh ringOfFiveWithSliver() {
  return ringAroundAxis(1.2, {{1.4, 0.5, 0.1}, {1.5, 1.5, 0.3}, {2.0, 1.2, 0.2}, {3.2, 0.5, 0.0}, {5.9, 0.8, 0.1}});
}

TetMesh ringOfFourWithSliver() {
  return ringAroundAxis(1.9, {{1.2, 0.5, 0.0}, {2.0, 1.4, 0.0}, {3.2, 0.9, 0.2}, {4.5, 0.7, 0.0}});
}

void setPoints(TetMesh& m, double h) {
  const double s = std::sqrt(3.0) / 2;
  m.points = {{1, 0, 0}, {-0.5, s, 0}, {-0.5, -s, 0}, {0, 0, h}, {0, 0, -h}};
  m.vertex_dimension.assign(5, 2);
  m.vertex_curve.assign(5, -1);
}

// The hull of the five points: six triangles, all on the outer boundary of material `mat`.
void addHull(TetMesh& m, int mat) {
  for (const auto& f : {std::array<int64_t, 3>{A, B, D}, {B, C, D}, {C, A, D}, {A, B, E}, {B, C, E}, {C, A, E}})
    m.boundary.push_back({f, mat, 0});
}

TetMesh twoTets(double h, int mat_d = 1, int mat_e = 1) {
  TetMesh m;
  setPoints(m, h);
  m.tets = {{A, B, C, D}, {A, B, C, E}};
  m.tet_materials = {mat_d, mat_e};
  orientAll(m);
  addHull(m, 1);
  return m;
}

TetMesh threeTets(double h) {
  TetMesh m;
  setPoints(m, h);
  m.tets = {{D, E, A, B}, {D, E, B, C}, {D, E, C, A}};
  m.tet_materials = {1, 1, 1};
  orientAll(m);
  addHull(m, 1);
  return m;
}

double minDihedralOf(const TetMesh& m) {
  double lo = 180;
  for (const auto& t : m.tets) {
    const auto a = dihedralAngles(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
    lo = std::min(lo, *std::min_element(a.begin(), a.end()));
  }
  return lo;
}

void expectValid(const TetMesh& before, const TetMesh& after) {
  for (const auto& t : after.tets)
    EXPECT_GT(test::orientation(after.points[t[0]], after.points[t[1]], after.points[t[2]], after.points[t[3]]), 0);
  const auto vb = test::volumePerMaterial(before), va = test::volumePerMaterial(after);
  ASSERT_EQ(vb.size(), va.size());
  for (const auto& [mat, vol] : vb) EXPECT_NEAR(va.at(mat), vol, 1e-9 * vol) << "material " << mat;
  // Each boundary triangle is still a face of exactly one tet.
  for (const auto& b : after.boundary) {
    int owners = 0;
    for (const auto& t : after.tets)
      owners += std::count(t.begin(), t.end(), b.v[0]) && std::count(t.begin(), t.end(), b.v[1]) &&
                std::count(t.begin(), t.end(), b.v[2]);
    EXPECT_EQ(owners, 1);
  }
  EXPECT_EQ(test::featureEdgesNotTetEdges(after), 0);
}

// A goal above every configuration here, so each is worked on.
ImprovementStats improve(TetMesh& m) {
  ImprovementOptions options;
  options.goal_deg = 70;
  return improveMesh(m, options, RunControl());
}

TEST(ImproveShape, SmallestDihedralIsTheSmallestOfTheSix) {
  uint64_t state = 12345;
  auto next = [&] { return (state = state * 6364136223846793005ULL + 1442695040888963407ULL) / 18446744073709551616.0; };
  for (int trial = 0; trial < 2000; ++trial) {
    Point3 p[4];
    for (auto& q : p) q = {next(), next(), next()};
    if (trial % 3 == 0) p[3] = p[0] + 0.3 * (p[1] - p[0]) + 0.4 * (p[2] - p[0]) + Point3{0, 0, 1e-7 * next()};
    const auto angles = dihedralAngles(p[0], p[1], p[2], p[3]);
    const double expected = *std::min_element(angles.begin(), angles.end());
    EXPECT_NEAR(smallestDihedral(p[0], p[1], p[2], p[3]), expected, 1e-9 + 1e-9 * expected) << trial;
  }
}

TEST(ImproveFlips, TwoThreeFlipFixesFlatPair) {
  const TetMesh before = twoTets(0.2);
  TetMesh m = before;
  const ImprovementStats s = improve(m);
  EXPECT_EQ(s.flips23, 1);
  EXPECT_EQ(m.tets.size(), 3u);
  EXPECT_NEAR(s.min_dihedral_before, 21.80, 0.01);
  EXPECT_NEAR(s.min_dihedral_after, 43.60, 0.01);
  EXPECT_NEAR(minDihedralOf(m), s.min_dihedral_after, 1e-12);
  EXPECT_TRUE(test::hasTetEdge(m, D, E));
  expectValid(before, m);
}

TEST(ImproveFlips, ThreeTwoFlipRemovesLongInteriorEdge) {
  const TetMesh before = threeTets(1.0);
  TetMesh m = before;
  const ImprovementStats s = improve(m);
  EXPECT_EQ(s.flips32, 1);
  EXPECT_EQ(m.tets.size(), 2u);
  EXPECT_GT(s.min_dihedral_after, s.min_dihedral_before + 20);
  EXPECT_FALSE(test::hasTetEdge(m, D, E));
  expectValid(before, m);
}

TEST(ImproveFlips, NoFlipWhenItWouldNotImprove) {
  for (TetMesh m : {twoTets(1.0), threeTets(0.2)}) {
    const TetMesh before = m;
    const ImprovementStats s = improve(m);
    EXPECT_EQ(s.flips23 + s.flips32, 0);
    EXPECT_EQ(m.tets, before.tets);
  }
}

TEST(ImproveFlips, InterfaceBetweenMaterialsIsNotFlipped) {
  TetMesh m = twoTets(0.2, 1, 2);
  m.boundary.push_back({{A, B, C}, 1, 2});  // the interface face abc
  const TetMesh before = m;
  const ImprovementStats s = improve(m);
  EXPECT_EQ(s.flips23, 0);
  EXPECT_EQ(m.tets, before.tets);
  EXPECT_EQ(m.tet_materials, before.tet_materials);
}

TEST(ImproveFlips, FlipThatWouldInvertIsRefused) {
  // Apexes off-axis beyond the edge bc: segment de no longer pierces triangle abc, so the 2-3
  // flip would make an inverted tet, although the flat pair would gain from it otherwise.
  TetMesh m = twoTets(0.2);
  m.points[D] = {-1.5, 0, 0.2};
  m.points[E] = {-1.5, 0, -0.2};
  orientAll(m);
  const TetMesh before = m;
  ImprovementMesh work(m);
  EXPECT_EQ(removeFaces(work, A, B, C), 0);
  EXPECT_EQ(removeFaces(work, A, C, B), 0);
  const ImprovementStats s = improve(m);
  EXPECT_EQ(s.flips23, 0);
  EXPECT_EQ(m.tets, before.tets);
}

// Removing the axis of five tets gives six (three triangles of the ring, each joined to both
// apexes).
TEST(ImproveEdgeRemoval, RingOfFiveKeepsVolumeAndOrientation) {
  const TetMesh before = ringOfFiveWithSliver();
  TetMesh m = before;
  ImprovementMesh work(m);
  const double q0 = minDihedralOf(m);
  ASSERT_EQ(removeEdge(work, 0, 1), 5);
  work.writeBack(m);
  EXPECT_EQ(m.tets.size(), 6u);
  EXPECT_FALSE(test::hasTetEdge(m, 0, 1));
  EXPECT_NEAR(q0, 4.2, 0.05);
  EXPECT_NEAR(minDihedralOf(m), 40.7, 0.05);
  expectValid(before, m);
}

TEST(ImproveEdgeRemoval, RingOfFourIsTheFourFourFlip) {
  const TetMesh before = ringOfFourWithSliver();
  TetMesh m = before;
  const ImprovementStats s = improve(m);
  EXPECT_EQ(s.flips44, 1);
  EXPECT_FALSE(test::hasTetEdge(m, 0, 1));
  EXPECT_EQ(m.tets.size(), 4u);
  expectValid(before, m);
}

TEST(ImproveEdgeRemoval, FeatureEdgeIsNeverRemoved) {
  for (int n : {3, 4, 5, 6}) {
    TetMesh m = n == 4 ? ringOfFourWithSliver() : n == 5 ? ringOfFiveWithSliver() : ringAroundAxis(n, 1.0);
    m.feature_edges = {{1, 0}};
    m.feature_edge_curves = {0};
    ImprovementMesh work(m);
    EXPECT_EQ(removeEdge(work, 0, 1), 0) << n;
    improve(m);
    EXPECT_TRUE(test::hasTetEdge(m, 0, 1)) << n;
  }
}

TEST(ImproveEdgeRemoval, RingOfMixedMaterialsIsKept) {
  TetMesh m = ringOfFiveWithSliver();
  m.tet_materials[2] = 2;
  ImprovementMesh work(m);
  EXPECT_EQ(removeEdge(work, 0, 1), 0);
}

// The regular pentagon r_0..r_4 (vertices 2..6, unit circle, z = 0) fanned from r_0, each of
// its three triangles joined to d = (0, 0, h) and to e = (0, 0, -h) (vertices 0 and 1): the
// triangles are sandwiched between d and e, and removing all three gives the five tets around
// de. At h = 0.5 the six tets reach 31.7 degrees, the five 63.4; the middle face alone gives
// 36.0 (its tets over the chords r_0 r_2 and r_3 r_0). At h = 1.2 the five (60.8 against
// 37.9) have a circumradius of 1.23 and a radius-edge ratio of 1.05 against 1.02 and 0.87.
TetMesh fannedPentagon(double h) {
  TetMesh m;
  m.points = {{0, 0, h}, {0, 0, -h}};
  for (int i = 0; i < 5; ++i) m.points.push_back({std::cos(2 * M_PI * i / 5), std::sin(2 * M_PI * i / 5), 0});
  for (int64_t k = 3; k <= 5; ++k)
    for (int64_t apex : {0, 1}) {
      m.tets.push_back({apex, 2, k, k + 1});
      m.tet_materials.push_back(1);
    }
  for (int64_t i = 0; i < 5; ++i)
    for (int64_t apex : {0, 1}) m.boundary.push_back({{apex, 2 + i, 2 + (i + 1) % 5}, 1, 0});
  orientAll(m);
  m.vertex_dimension.assign(m.points.size(), 2);
  m.vertex_curve.assign(m.points.size(), -1);
  return m;
}

bool everyTetHas(const TetMesh& m, int64_t u, int64_t v) {
  return std::all_of(m.tets.begin(), m.tets.end(),
                     [&](const TetCorners& t) { return std::count(t.begin(), t.end(), u) && std::count(t.begin(), t.end(), v); });
}

TEST(ImproveFaceRemoval, SandwichedFacesBecomeTheRingAroundTheApexes) {
  const TetMesh before = fannedPentagon(0.5);
  TetMesh m = before;
  ImprovementMesh work(m);
  EXPECT_NEAR(minDihedralOf(m), 31.7, 0.05);
  ASSERT_EQ(removeFaces(work, 2, 4, 5), 3);
  work.writeBack(m);
  EXPECT_EQ(m.tets.size(), 5u);
  EXPECT_TRUE(everyTetHas(m, 0, 1));
  EXPECT_NEAR(minDihedralOf(m), 63.4, 0.05);
  expectValid(before, m);
}

TEST(ImproveFaceRemoval, FeatureEdgeBoundsTheDisk) {
  TetMesh before = fannedPentagon(0.5);
  before.feature_edges = {{2, 4}};  // the chord r_0 r_2 between the first two triangles
  before.feature_edge_curves = {0};
  TetMesh m = before;
  ImprovementMesh work(m);
  SizeCriteria sizes;  // the tet over the chord kept is bigger (circumradius 1.31 against 1.25)
  sizes.cell = [](int, const Point3&) { return 2.0; };
  sizes.cell_ratio = [](int) { return 2.0; };
  EXPECT_EQ(removeFaces(work, 2, 4, 5, sizes), 2);  // the middle face and the one beyond r_3 r_0
  work.writeBack(m);
  EXPECT_EQ(m.tets.size(), 6u);
  EXPECT_TRUE(test::hasTetEdge(m, 2, 4));
  EXPECT_NEAR(minDihedralOf(m), 31.7, 0.05);  // the two tets beyond the chord stay
  expectValid(before, m);
}

// New tets bigger than every tet they replace are admitted only within the job's criteria.
TEST(ImproveSizeBound, LargerTetsOnlyWithinTheCellSizeAndRatio) {
  auto removed = [](double cellSize, double ratio) {
    TetMesh m = fannedPentagon(1.2);
    ImprovementMesh work(m);
    SizeCriteria sizes;
    if (cellSize > 0) sizes.cell = [cellSize](int, const Point3&) { return cellSize; };
    if (ratio > 0) sizes.cell_ratio = [ratio](int) { return ratio; };
    return removeFaces(work, 2, 4, 5, sizes);
  };
  EXPECT_EQ(removed(0, 0), 0);    // no criteria: no tet bigger than the old ones
  EXPECT_EQ(removed(2, 2), 3);    // both criteria hold
  EXPECT_EQ(removed(1.1, 2), 0);  // circumradius 1.23 over the cell size
  EXPECT_EQ(removed(2, 1.0), 0);  // ratio 1.05 over its bound
  EXPECT_EQ(removed(2, 0), 0);    // no ratio bound given
}

// A pyramid over the quadrilateral `base` (counter-clockwise in z = 0) with its apex at
// (0, 0, 1), fanned from a vertex v of the base: every base triangle is on the boundary.
TetMesh pyramidFannedFrom(const Point3& v, const std::array<Point3, 4>& base) {
  TetMesh m;
  m.points = {v, base[0], base[1], base[2], base[3], {0, 0, 1}};
  for (int64_t i = 0; i < 4; ++i) {
    const int64_t r = 1 + i, s = 1 + (i + 1) % 4;
    m.tets.push_back({0, r, s, 5});
    m.tet_materials.push_back(1);
    m.boundary.push_back({{0, s, r}, 1, 0});
    m.boundary.push_back({{r, s, 5}, 1, 0});
  }
  orientAll(m);
  m.vertex_dimension = {2, 0, 0, 0, 0, 0};
  m.vertex_curve.assign(6, -1);
  return m;
}

// Over the square (+-1, +-1, 0), v off centre at (0.8, 0.1, 0).
TetMesh fanOverPlanarBase() { return pyramidFannedFrom({0.8, 0.1, 0}, {{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}}); }

TEST(ImproveSmoothing, SurfaceVertexStaysInItsPlane) {
  const TetMesh before = fanOverPlanarBase();
  TetMesh m = before;
  ImprovementMesh work(m);
  ASSERT_EQ(work.mobility(0).freedom, VertexFreedom::Planar);
  EXPECT_EQ(work.mobility(5).freedom, VertexFreedom::Fixed);  // the apex: on four planes
  const double q0 = minDihedralOf(m);
  ASSERT_TRUE(smoothVertex(work, 0));
  EXPECT_EQ(m.points[0][2], 0.0);
  EXPECT_LT(std::hypot(m.points[0][0], m.points[0][1]), 0.5);  // towards the centre
  EXPECT_GT(minDihedralOf(m), q0 + 5);
  for (int64_t v = 1; v < 6; ++v) EXPECT_EQ(m.points[v], before.points[v]);
  expectValid(before, m);
}

TEST(ImproveSmoothing, SurfaceVertexOfTwoInterfacesStays) {
  TetMesh m = fanOverPlanarBase();
  m.boundary[0].material_out = 2;  // the base triangles meet two other materials at v
  ImprovementMesh work(m);
  EXPECT_EQ(work.mobility(0).freedom, VertexFreedom::Fixed);
  EXPECT_FALSE(smoothVertex(work, 0));
}

// The same pyramid over the square with corners (+-1, 0, 0), (0, +-1, 0), with a straight
// feature curve (curve 7) across its base from (-1, 0, 0) through v at (x, 0, 0) to (1, 0, 0).
TetMesh pyramidWithLineThrough(double x) {
  TetMesh m = pyramidFannedFrom({x, 0, 0}, {{{-1, 0, 0}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}}});
  m.feature_edges = {{1, 0}, {0, 3}};
  m.feature_edge_curves = {7, 7};
  m.vertex_dimension[0] = 1;
  m.vertex_curve[0] = 7;
  return m;
}

// v at (0.7, 0, 0) may move along the x axis only.
TEST(ImproveSmoothing, FeatureVertexStaysOnItsLine) {
  TetMesh m = pyramidWithLineThrough(0.7);
  const TetMesh before = m;
  ImprovementMesh work(m);
  ASSERT_EQ(work.mobility(0).freedom, VertexFreedom::Linear);
  const double q0 = minDihedralOf(m);
  ASSERT_TRUE(smoothVertex(work, 0));
  EXPECT_EQ(m.points[0][1], 0.0);
  EXPECT_EQ(m.points[0][2], 0.0);
  EXPECT_LT(m.points[0][0], 0.6);
  EXPECT_GT(minDihedralOf(m), q0);
  expectValid(before, m);
}

// Puts points back onto analytic shapes for the curved cases: a sphere for surface vertices,
// a circle in z = 0 for curve vertices.
class AnalyticPlacement final : public BoundaryPlacement {
 public:
  AnalyticPlacement(const Point3& centre, double radius) : centre_(centre), radius_(radius) {}
  std::optional<Point3> ontoSurface(int64_t, const Point3& q) const override {
    const Point3 d = q - centre_;
    return centre_ + (radius_ / norm(d)) * d;
  }
  std::optional<Point3> ontoCurve(int64_t, const Point3& q) const override {
    const Point3 d{q[0] - centre_[0], q[1] - centre_[1], 0};
    return Point3{centre_[0], centre_[1], 0} + (radius_ / norm(d)) * d;
  }

 private:
  Point3 centre_;
  double radius_;
};

// The fan of pyramidFannedFrom over a base on the sphere of radius 3 centred at (0, 0, -3):
// corners (+-1, +-1) and v at (0.8, 0.1), lifted onto the sphere.
constexpr double kSphereRadius = 3;
const Point3 kSphereCentre{0, 0, -kSphereRadius};
Point3 onSphere(double x, double y) {
  return {x, y, std::sqrt(kSphereRadius * kSphereRadius - x * x - y * y) - kSphereRadius};
}
TetMesh fanOverSphericalBase() {
  return pyramidFannedFrom(onSphere(0.8, 0.1), {{onSphere(-1, -1), onSphere(1, -1), onSphere(1, 1), onSphere(-1, 1)}});
}

TEST(ImproveSmoothing, CurvedSurfaceVertexStaysOnItsSurface) {
  const TetMesh before = fanOverSphericalBase();
  TetMesh m = before;
  const AnalyticPlacement sphere(kSphereCentre, kSphereRadius);
  ImprovementMesh work(m, &sphere, 1.0);
  ASSERT_EQ(work.mobility(0).freedom, VertexFreedom::Curved);
  const double q0 = minDihedralOf(m);
  ASSERT_TRUE(smoothVertex(work, 0));
  EXPECT_NEAR(distance(m.points[0], kSphereCentre), kSphereRadius, 1e-12);
  EXPECT_LT(std::hypot(m.points[0][0], m.points[0][1]), 0.5);  // towards the centre
  EXPECT_GT(minDihedralOf(m), q0 + 5);
  for (int64_t v = 1; v < 6; ++v) EXPECT_EQ(m.points[v], before.points[v]);
  for (const auto& t : m.tets)
    EXPECT_GT(test::orientation(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]), 0);
  // The chords over the sphere changed, so the volume did, and the stage counted it.
  const double share = std::abs(test::volumePerMaterial(m).at(1) / test::volumePerMaterial(before).at(1) - 1);
  EXPECT_GT(share, 0);
  EXPECT_NEAR(work.largestVolumeShareChanged(), share, 1e-12);
}

// The bound is on each material's net change: a change back the other way always fits, one
// that would take the net past the bound on either side never does.
TEST(ImproveSmoothing, CurvedVolumeBoundIsOnTheNetChange) {
  TetMesh m = fanOverSphericalBase();
  const double volume = test::volumePerMaterial(m).at(1);
  const AnalyticPlacement sphere(kSphereCentre, kSphereRadius);
  const double bound = 1e-3;
  ImprovementMesh work(m, &sphere, bound);
  const double limit = bound * volume;
  ASSERT_TRUE(work.volumeFits({{1, 0.8 * limit}}));
  work.addVolumeChange({{1, 0.8 * limit}});
  EXPECT_FALSE(work.volumeFits({{1, 0.4 * limit}}));
  EXPECT_TRUE(work.volumeFits({{1, -1.5 * limit}}));  // to -0.7: its absolute sum would be 2.3
  EXPECT_FALSE(work.volumeFits({{1, -1.9 * limit}}));
  work.addVolumeChange({{1, -1.5 * limit}});
  EXPECT_NEAR(work.largestVolumeShareChanged(), 0.7 * bound, 1e-12);
  EXPECT_TRUE(work.volumeFits({{1, 1.6 * limit}}));
  EXPECT_FALSE(work.volumeFits({{2, 1e-30}}));  // a material the mesh does not have
}

TEST(ImproveSmoothing, CurvedSurfaceVertexStaysWithoutAPlacementOrVolumeBound) {
  TetMesh m = fanOverSphericalBase();
  ImprovementMesh fixed(m);
  EXPECT_EQ(fixed.mobility(0).freedom, VertexFreedom::Fixed);
  EXPECT_FALSE(smoothVertex(fixed, 0));
  const AnalyticPlacement sphere(kSphereCentre, kSphereRadius);
  ImprovementMesh noVolume(m, &sphere, 0.0);
  ASSERT_EQ(noVolume.mobility(0).freedom, VertexFreedom::Curved);
  EXPECT_FALSE(smoothVertex(noVolume, 0));
  EXPECT_EQ(m.points, fanOverSphericalBase().points);
}

// A curved feature curve across the planar base of the square (-1, 0, 0) (0, -1, 0) (1, 0, 0)
// (0, 1, 0): the arc of the circle through (-1, 0, 0) and (1, 0, 0) centred at (0, -2, 0), v on
// it at x = 0.7. v moves along the arc and stays on it.
TEST(ImproveSmoothing, CurvedFeatureVertexStaysOnItsCurve) {
  const double radius = std::sqrt(5.0);
  TetMesh m = pyramidFannedFrom({0.7, std::sqrt(5 - 0.49) - 2, 0}, {{{-1, 0, 0}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}}});
  m.feature_edges = {{1, 0}, {0, 3}};
  m.feature_edge_curves = {7, 7};
  m.vertex_dimension[0] = 1;
  m.vertex_curve[0] = 7;
  const TetMesh before = m;
  const AnalyticPlacement circle({0, -2, 0}, radius);
  ImprovementMesh work(m, &circle, 1.0);
  ASSERT_EQ(work.mobility(0).freedom, VertexFreedom::OnCurve);
  const double q0 = minDihedralOf(m);
  ASSERT_TRUE(smoothVertex(work, 0));
  EXPECT_EQ(m.points[0][2], 0.0);
  EXPECT_NEAR(std::hypot(m.points[0][0], m.points[0][1] + 2), radius, 1e-12);
  EXPECT_LT(m.points[0][0], 0.6);
  EXPECT_GT(minDihedralOf(m), q0);
  expectValid(before, m);  // the base is planar: no volume moved
}

TEST(ImproveSmoothing, CornerNeverMoves) {
  TetMesh m = fanOverPlanarBase();
  m.vertex_dimension[0] = 0;
  ImprovementMesh work(m);
  EXPECT_EQ(work.mobility(0).freedom, VertexFreedom::Fixed);
  EXPECT_FALSE(smoothVertex(work, 0));
}

// The cube [-1, 1]^3 as twelve tets joining its boundary triangles (each face split through
// its corners 0 or 7) to an interior vertex v = 8 at `v`.
TetMesh cubeFannedFrom(const Point3& v) {
  TetMesh m;
  for (int i = 0; i < 8; ++i) m.points.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
  m.points.push_back(v);
  const int64_t quads[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& q : quads)
    for (const auto& f : {std::array<int64_t, 3>{q[0], q[1], q[2]}, {q[0], q[2], q[3]}}) {
      m.tets.push_back({f[0], f[1], f[2], 8});
      m.tet_materials.push_back(1);
      m.boundary.push_back({f, 1, 0});
    }
  orientAll(m);
  m.vertex_dimension = {0, 0, 0, 0, 0, 0, 0, 0, 3};
  m.vertex_curve.assign(9, -1);
  return m;
}

// v placed off centre moves freely, towards the centre, and the volume stays 8.
TEST(ImproveSmoothing, InteriorVertexMovesFreely) {
  TetMesh m = cubeFannedFrom({0.6, 0.2, -0.3});
  const int64_t v = 8;
  const TetMesh before = m;
  ImprovementMesh work(m);
  ASSERT_EQ(work.mobility(v).freedom, VertexFreedom::Free);
  const double q0 = minDihedralOf(m);
  ASSERT_TRUE(smoothVertex(work, v));
  EXPECT_LT(norm(m.points[v]), norm(before.points[v]));
  EXPECT_GT(minDihedralOf(m), q0);
  expectValid(before, m);
  EXPECT_NEAR(test::volumePerMaterial(m).at(1), 8.0, 1e-12);
}

// v at (0.95, -0.9, 0), next to the base corner (1, -1, 0): the short edge makes two flat tets
// that smoothing in the plane would have to undo; the collapse takes v out instead.
TEST(ImproveCollapse, PlanarVertexGoesOntoACornerOfItsPatch) {
  const TetMesh before = pyramidFannedFrom({0.95, -0.9, 0}, {{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}});
  TetMesh m = before;
  ImprovementMesh work(m);
  ASSERT_EQ(work.mobility(0).freedom, VertexFreedom::Planar);
  EXPECT_FALSE(collapseEdge(work, 0, 5));  // the apex is off the patch
  ASSERT_TRUE(collapseEdge(work, 0, 2));
  EXPECT_TRUE(work.removed(0));
  const std::vector<int64_t> previous = work.writeBack(m);
  EXPECT_EQ(previous, (std::vector<int64_t>{1, 2, 3, 4, 5}));
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.vertex_dimension.size(), 5u);
  EXPECT_EQ(m.vertex_curve.size(), 5u);
  EXPECT_EQ(m.tets.size(), 2u);  // the square pyramid as two tets
  EXPECT_EQ(m.boundary.size(), 6u);
  EXPECT_GT(minDihedralOf(m), minDihedralOf(before) + 20);
  expectValid(before, m);
}

TEST(ImproveCollapse, VertexOfTwoInterfacesStays) {
  TetMesh m = pyramidFannedFrom({0.95, -0.9, 0}, {{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}});
  m.boundary[0].material_out = 2;
  ImprovementMesh work(m);
  ASSERT_EQ(work.mobility(0).freedom, VertexFreedom::Fixed);
  for (int64_t u = 1; u < 6; ++u) EXPECT_FALSE(collapseEdge(work, 0, u));
}

// v at (0.9, 0, 0) goes onto its curve neighbour (1, 0, 0) only when the curve segment that
// makes, 2 long, is within the edge size; the curve is then one feature edge of the mesh.
TEST(ImproveCollapse, FeatureVertexGoesAlongItsLineWithinTheEdgeSize) {
  TetMesh m = pyramidWithLineThrough(0.9);
  const TetMesh before = m;
  ImprovementMesh work(m);
  ASSERT_EQ(work.mobility(0).freedom, VertexFreedom::Linear);
  // The base triangles at v have circumradii up to 0.95; the two that replace them have 1.
  auto sizes = [](double edge, double facet) {
    return SizeCriteria{[edge](const Point3&) { return edge; }, [facet](int, const Point3&) { return facet; }};
  };
  EXPECT_FALSE(collapseEdge(work, 0, 3));  // no sizes: curve vertices stay
  EXPECT_FALSE(collapseEdge(work, 0, 3, sizes(1.9, 1.001)));
  EXPECT_FALSE(collapseEdge(work, 0, 3, sizes(2, 0.99)));
  EXPECT_FALSE(collapseEdge(work, 0, 2, sizes(5, 5)));  // not along the curve
  ASSERT_TRUE(collapseEdge(work, 0, 3, sizes(2, 1.001)));
  work.writeBack(m);
  ASSERT_EQ(m.feature_edges.size(), 1u);
  EXPECT_EQ(std::minmax(m.feature_edges[0][0], m.feature_edges[0][1]), std::minmax<int64_t>(0, 2));  // old 1 and 3
  EXPECT_EQ(m.feature_edge_curves, std::vector<int>{7});
  EXPECT_GT(minDihedralOf(m), minDihedralOf(before));
  expectValid(before, m);
}

// The cube fanned from v at (0.9, 0.9, 0.9): onto the corner (1, 1, 1), whose three faces are
// split through it, the cube becomes six tets fanned from that corner; onto (1, -1, -1) a tet
// would be flat (a face diagonal misses that corner).
TEST(ImproveCollapse, InteriorVertexGoesOntoACornerOnlyWhereNoTetGoesFlat) {
  TetMesh m = cubeFannedFrom({0.9, 0.9, 0.9});
  const int64_t v = 8;
  const TetMesh before = m;
  ImprovementMesh work(m);
  ASSERT_EQ(work.mobility(v).freedom, VertexFreedom::Free);
  EXPECT_FALSE(collapseEdge(work, v, 1));
  ASSERT_TRUE(collapseEdge(work, v, 7));
  work.writeBack(m);
  EXPECT_EQ(m.points.size(), 8u);
  EXPECT_EQ(m.tets.size(), 6u);
  EXPECT_EQ(m.boundary.size(), 12u);
  EXPECT_GT(minDihedralOf(m), minDihedralOf(before));
  expectValid(before, m);
  EXPECT_NEAR(test::volumePerMaterial(m).at(1), 8.0, 1e-12);
}

// A sliver between two caps, every vertex a corner of the hull (none can move or go): four
// ring points at radius 1, alternately 0.05 above and below z = 0, make the sliver; the apexes
// (0, 0, +-1) each cap its two faces that face them. Five tets, eight hull triangles; the caps
// are of `capMaterial` (the faces between them and the sliver are then interfaces).
TetMesh sliverBetweenCaps(int capMaterial = 1) {
  TetMesh m;
  m.points = {{1, 0, 0.05}, {0, 1, -0.05}, {-1, 0, 0.05}, {0, -1, -0.05}, {0, 0, 1}, {0, 0, -1}};
  const int64_t north = 4, south = 5;
  m.tets = {{0, 1, 2, 3}};
  m.tet_materials = {1};
  for (const auto& f : {std::array<int64_t, 3>{0, 1, 2}, {0, 2, 3}, {0, 1, 3}, {1, 2, 3}}) {
    // The sliver's face faces the apex on the side its fourth ring point is not.
    int64_t rest = 0;
    while (std::count(f.begin(), f.end(), rest)) ++rest;
    const double side = test::orientation(m.points[f[0]], m.points[f[1]], m.points[f[2]], m.points[rest]);
    const int64_t apex = test::orientation(m.points[f[0]], m.points[f[1]], m.points[f[2]], m.points[north]) * side < 0 ? north : south;
    m.tets.push_back({f[0], f[1], f[2], apex});
    m.tet_materials.push_back(capMaterial);
    if (capMaterial != 1) m.boundary.push_back({f, 1, capMaterial});
  }
  orientAll(m);
  for (int64_t i = 0; i < 4; ++i)
    for (int64_t apex : {north, south}) m.boundary.push_back({{i, (i + 1) % 4, apex}, capMaterial, 0});
  m.vertex_dimension.assign(m.points.size(), 0);
  m.vertex_curve.assign(m.points.size(), -1);
  return m;
}

// A new vertex makes edges shorter than the old tets' (its star's radius-edge ratios, 0.87, are
// above the sliver's and caps', 0.71): admitted within the job's ratio bound.
SizeCriteria ratioBound(double ratio) {
  SizeCriteria sizes;
  sizes.cell = [](int, const Point3&) { return 10.0; };
  sizes.cell_ratio = [ratio](int) { return ratio; };
  return sizes;
}

// The new vertex at the origin (the sliver's centroid) replaces all five tets by the eight of
// its star, each over a hull triangle.
TEST(ImproveInsertion, NewVertexReplacesTheSliverAndItsCapsByItsStar) {
  const TetMesh before = sliverBetweenCaps();
  ASSERT_LT(minDihedralOf(before), 10);
  TetMesh m = before;
  ImprovementMesh work(m);
  EXPECT_EQ(insertVertex(work, 0), -1) << "without a ratio bound above the star's";
  const int64_t v = insertVertex(work, 0, ratioBound(2));
  ASSERT_EQ(v, 6);
  EXPECT_EQ(work.mobility(v).freedom, VertexFreedom::Free);
  const std::vector<int64_t> previous = work.writeBack(m);
  EXPECT_EQ(previous, (std::vector<int64_t>{0, 1, 2, 3, 4, 5, -1}));
  ASSERT_EQ(m.points.size(), 7u);
  EXPECT_EQ(m.vertex_dimension.back(), 3);
  EXPECT_EQ(m.vertex_curve.back(), -1);
  EXPECT_EQ(m.tets.size(), 8u);
  for (const auto& t : m.tets) EXPECT_EQ(std::count(t.begin(), t.end(), v), 1);
  EXPECT_EQ(m.boundary.size(), 8u);
  EXPECT_GT(minDihedralOf(m), minDihedralOf(before) + 20);
  expectValid(before, m);
}

// Nothing of another material, no interface triangle and no feature edge is taken: with the
// caps of material 2 the cavity is the sliver alone, and its star (four tets from its centroid)
// is worse than the sliver; with the sliver's diagonal a feature edge every star over the
// whole cavity would lose that edge.
TEST(ImproveInsertion, CavityStopsAtInterfacesAndKeepsFeatureEdges) {
  {
    const TetMesh before = sliverBetweenCaps(2);
    TetMesh m = before;
    ImprovementMesh work(m);
    EXPECT_EQ(insertVertex(work, 0, ratioBound(100)), -1);
    work.writeBack(m);
    EXPECT_EQ(m.tets, before.tets);
  }
  {
    TetMesh before = sliverBetweenCaps();
    before.feature_edges = {{0, 2}};
    before.feature_edge_curves = {0};
    TetMesh m = before;
    ImprovementMesh work(m);
    insertVertex(work, 0, ratioBound(100));
    work.writeBack(m);
    EXPECT_TRUE(test::hasTetEdge(m, 0, 2));
    expectValid(before, m);
  }
}

TEST(ImproveDriver, Deterministic) {
  TetMesh a = ringOfFiveWithSliver(), b = ringOfFiveWithSliver();
  improve(a);
  improve(b);
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.points, b.points);
  TetMesh c = fanOverPlanarBase(), d = fanOverPlanarBase();
  improve(c);
  improve(d);
  EXPECT_EQ(c.points, d.points);
}

}  // namespace
}  // namespace oraclemesh
