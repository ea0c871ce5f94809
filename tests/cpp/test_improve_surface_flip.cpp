// The 2-2 surface flip (src/core/improve/SurfaceFlip) on a thin rhombus a c b d in the plane
// z = 0: a = (-1, 0, 0) and b = (1, 0, 0) on its long diagonal, c = (0, -w, 0) and d = (0, w, 0)
// on its short one. Above it the apex p = (0, 0, 1) makes two tets abcp and abdp, thin across
// ab (their faces at edge ap meet at about 2 w radians); the surface triangles abc and abd are
// needles. Flipping ab to cd makes the tets cdpa and cdpb, each a good tet on its own side of the
// plane x = 0. Below the plane, an apex q = (0, 0, -1) of material 2 makes the rhombus an
// interface instead of the outer boundary.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <set>

#include "improve/BoundaryPlacement.h"
#include "improve/ImprovementMesh.h"
#include "improve/MeshImprovement.h"
#include "improve/SurfaceFlip.h"
#include "improve/TetShape.h"
#include "mesh/Topology.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"

namespace oraclemesh {
namespace {

constexpr int64_t A = 0, B = 1, C = 2, D = 3, P = 4, Q = 5;

// The tets over the rhombus (and under it with `withLower`), the boundary extracted from them.
TetMesh rhombus(double w, bool withLower, const Point3& c = {0, -1, 0}) {
  TetMesh m;
  m.points = {{-1, 0, 0}, {1, 0, 0}, {c[0], w * c[1], c[2]}, {0, w, 0}, {0, 0, 1}, {0, 0, -1}};
  m.tets = {{A, B, C, P}, {A, B, D, P}};
  m.tet_materials = {1, 1};
  if (withLower) {
    m.tets.push_back({A, B, C, Q});
    m.tets.push_back({A, B, D, Q});
    m.tet_materials.push_back(2);
    m.tet_materials.push_back(2);
  }
  for (auto& t : m.tets)
    if (test::orientation(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) < 0) std::swap(t[0], t[1]);
  m.vertex_dimension = {2, 2, 2, 2, 2, 2};
  m.vertex_curve.assign(6, -1);
  if (!withLower) {
    m.points.pop_back();
    m.vertex_dimension.pop_back();
    m.vertex_curve.pop_back();
  }
  m.boundary = extractBoundary(m);
  return m;
}

std::set<std::array<int64_t, 3>> boundaryFaces(const TetMesh& m, int materialIn, int materialOut) {
  std::set<std::array<int64_t, 3>> faces;
  for (const auto& b : m.boundary)
    if (std::minmax(b.material_in, b.material_out) == std::minmax(materialIn, materialOut)) {
      std::array<int64_t, 3> f = b.v;
      std::sort(f.begin(), f.end());
      faces.insert(f);
    }
  return faces;
}

double smallestAngle(const TetMesh& m) {
  double lo = 180;
  for (const auto& t : m.tets) lo = std::min(lo, smallestDihedral(m.points, t));
  return lo;
}

void expectSameVolumesAndPositive(const TetMesh& before, const TetMesh& after) {
  for (const auto& t : after.tets)
    EXPECT_GT(test::orientation(after.points[t[0]], after.points[t[1]], after.points[t[2]], after.points[t[3]]), 0);
  const auto vb = test::volumePerMaterial(before), va = test::volumePerMaterial(after);
  ASSERT_EQ(vb.size(), va.size());
  for (const auto& [material, volume] : vb) EXPECT_NEAR(va.at(material), volume, 1e-12 * volume) << material;
}

TEST(ImproveSurfaceFlip, NeedlesOnTheOuterBoundaryBecomeTheShortDiagonal) {
  const TetMesh before = rhombus(0.15, false);
  TetMesh m = before;
  ImprovementMesh work(m);
  ASSERT_TRUE(flipSurfaceEdge(work, A, B));
  EXPECT_TRUE(work.writeBack(m).empty());  // no vertex added or removed
  EXPECT_FALSE(test::hasTetEdge(m, A, B));
  EXPECT_TRUE(test::hasTetEdge(m, C, D));
  const auto outer = boundaryFaces(m, 1, 0);
  EXPECT_EQ(outer.count({A, C, D}), 1u);
  EXPECT_EQ(outer.count({B, C, D}), 1u);
  EXPECT_EQ(outer.count({A, B, C}), 0u);
  EXPECT_EQ(outer.count({A, B, D}), 0u);
  EXPECT_EQ(outer.size(), boundaryFaces(before, 1, 0).size());
  EXPECT_GT(smallestAngle(m), smallestAngle(before) + 10);
  expectSameVolumesAndPositive(before, m);
}

TEST(ImproveSurfaceFlip, AnInterfaceIsFlippedOnBothSides) {
  const TetMesh before = rhombus(0.15, true);
  TetMesh m = before;
  ImprovementMesh work(m);
  ASSERT_TRUE(flipSurfaceEdge(work, A, B));
  work.writeBack(m);
  EXPECT_EQ(boundaryFaces(m, 1, 2), (std::set<std::array<int64_t, 3>>{{A, C, D}, {B, C, D}}));
  EXPECT_EQ(std::count(m.tet_materials.begin(), m.tet_materials.end(), 1), 2);
  EXPECT_EQ(std::count(m.tet_materials.begin(), m.tet_materials.end(), 2), 2);
  EXPECT_FALSE(test::hasTetEdge(m, A, B));
  EXPECT_GT(smallestAngle(m), smallestAngle(before) + 10);
  expectSameVolumesAndPositive(before, m);
}

TEST(ImproveSurfaceFlip, RefusedOnAFeatureEdgeOffThePlaneOrOnANonConvexQuad) {
  {
    TetMesh m = rhombus(0.15, false);
    m.feature_edges = {{A, B}};
    m.feature_edge_curves = {0};
    ImprovementMesh work(m);
    EXPECT_FALSE(flipSurfaceEdge(work, A, B));
  }
  {
    // d lifted by 1e-3: the two needles are no longer one plane (a curved face's chords).
    TetMesh m = rhombus(0.15, false);
    m.points[D][2] = 1e-3;
    m.boundary = extractBoundary(m);
    ImprovementMesh work(m);
    EXPECT_FALSE(flipSurfaceEdge(work, A, B));
  }
  {
    // c beyond b: the quad a c b d is not convex at b, cd would leave the rhombus.
    const TetMesh before = rhombus(0.15, false, {3, -1, 0});
    TetMesh m = before;
    ImprovementMesh work(m);
    EXPECT_FALSE(flipSurfaceEdge(work, A, B));
    work.writeBack(m);
    EXPECT_EQ(m.tets, before.tets);
  }
}

// A surface flip moves no vertex; the placement only says the mesh's vertices lie on the model.
class StayingPlacement : public BoundaryPlacement {
 public:
  std::optional<Point3> ontoSurface(int64_t, const Point3& q) const override { return q; }
  std::optional<Point3> ontoCurve(int64_t, const Point3& q) const override { return q; }
};

// d lifted by 1e-3 (a nearly flat stretch of a curved face): with a placement the flip is
// allowed within the flatness, and the sliver abcd (5e-5, 1 / 2000 of each material's 0.1)
// changes sides, which the curved-move volume bound must admit and then counts.
TEST(ImproveSurfaceFlip, OnACurvedStretchTheChordsChangeWithinTheVolumeBound) {
  TetMesh lifted = rhombus(0.15, true);
  lifted.points[D][2] = 1e-3;
  lifted.boundary = extractBoundary(lifted);
  const StayingPlacement placement;
  {
    TetMesh m = lifted;
    ImprovementMesh work(m, &placement, 1e-5);
    EXPECT_FALSE(flipSurfaceEdge(work, A, B, SizeCriteria{}, 0.05));  // past the volume bound
    EXPECT_EQ(work.largestVolumeShareChanged(), 0);
  }
  {
    TetMesh m = lifted;
    ImprovementMesh work(m, &placement, 1e-3);
    EXPECT_FALSE(flipSurfaceEdge(work, A, B, SizeCriteria{}, 1e-4));  // past the flatness
    ASSERT_TRUE(flipSurfaceEdge(work, A, B, SizeCriteria{}, 0.05));
    work.writeBack(m);
    EXPECT_EQ(boundaryFaces(m, 1, 2), (std::set<std::array<int64_t, 3>>{{A, C, D}, {B, C, D}}));
    for (const auto& t : m.tets)
      EXPECT_GT(test::orientation(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]), 0);
    const auto vb = test::volumePerMaterial(lifted), va = test::volumePerMaterial(m);
    const double moved = va.at(1) - vb.at(1);
    EXPECT_NEAR(moved, -(va.at(2) - vb.at(2)), 1e-15);  // what one side gains the other loses
    EXPECT_NEAR(std::abs(moved), 0.15 * 1e-3 / 3, 1e-12);
    EXPECT_NEAR(work.largestVolumeShareChanged(), std::abs(moved) / std::min(vb.at(1), vb.at(2)), 1e-9);
  }
}

TEST(ImproveSurfaceFlip, TheDriverFlipsWhereNoInteriorOperationHelps) {
  const TetMesh before = rhombus(0.15, true);
  TetMesh m = before;
  ImprovementOptions options;
  options.surface_flips = false;
  options.vertex_insertion = false;
  const ImprovementStats without = improveMesh(m, options, RunControl());
  EXPECT_EQ(without.surface_flips, 0);
  EXPECT_LT(without.min_dihedral_after, 15);
  m = before;
  options.surface_flips = true;
  const ImprovementStats with = improveMesh(m, options, RunControl());
  EXPECT_GE(with.surface_flips, 1);
  EXPECT_GT(with.min_dihedral_after, without.min_dihedral_after + 10);
  expectSameVolumesAndPositive(before, m);
}

}  // namespace
}  // namespace oraclemesh
