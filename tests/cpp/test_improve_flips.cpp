// The 2-3 / 3-2 flips of src/core/improve on hand-built configurations: three points a, b, c
// on the unit circle in z = 0 and two apexes d = (0,0,h), e = (0,0,-h). At h = 0.2 the two
// tets abcd, abce are flat (21.8 degrees) and the three around de are better (43.6); at h = 1
// the three around de (39.2) are worse than the two (63.4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "improve/Flips.h"
#include "mesh/Quality.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"

namespace oraclemesh {
namespace {

constexpr int64_t A = 0, B = 1, C = 2, D = 3, E = 4;

void setPoints(TetMesh& m, double h) {
  const double s = std::sqrt(3.0) / 2;
  m.points = {{1, 0, 0}, {-0.5, s, 0}, {-0.5, -s, 0}, {0, 0, h}, {0, 0, -h}};
  m.vertex_dimension.assign(5, 2);
  m.vertex_curve.assign(5, -1);
}

void orientAll(TetMesh& m) {
  for (auto& t : m.tets)
    if (test::orientation(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) < 0) std::swap(t[0], t[1]);
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

bool hasEdge(const TetMesh& m, int64_t u, int64_t v) {
  for (const auto& t : m.tets)
    if (std::count(t.begin(), t.end(), u) && std::count(t.begin(), t.end(), v)) return true;
  return false;
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
}

TEST(ImproveFlips, TwoThreeFlipFixesFlatPair) {
  const TetMesh before = twoTets(0.2);
  TetMesh m = before;
  const FlipStats s = improveByFlips(m);
  EXPECT_EQ(s.flips23, 1);
  EXPECT_EQ(m.tets.size(), 3u);
  EXPECT_NEAR(s.min_dihedral_before, 21.80, 0.01);
  EXPECT_NEAR(s.min_dihedral_after, 43.60, 0.01);
  EXPECT_NEAR(minDihedralOf(m), s.min_dihedral_after, 1e-12);
  EXPECT_TRUE(hasEdge(m, D, E));
  expectValid(before, m);
}

TEST(ImproveFlips, ThreeTwoFlipRemovesLongInteriorEdge) {
  const TetMesh before = threeTets(1.0);
  TetMesh m = before;
  const FlipStats s = improveByFlips(m);
  EXPECT_EQ(s.flips32, 1);
  EXPECT_EQ(m.tets.size(), 2u);
  EXPECT_GT(s.min_dihedral_after, s.min_dihedral_before + 20);
  EXPECT_FALSE(hasEdge(m, D, E));
  expectValid(before, m);
}

TEST(ImproveFlips, NoFlipWhenItWouldNotImprove) {
  for (TetMesh m : {twoTets(1.0), threeTets(0.2)}) {
    const TetMesh before = m;
    const FlipStats s = improveByFlips(m);
    EXPECT_EQ(s.flips23 + s.flips32, 0);
    EXPECT_EQ(m.tets, before.tets);
  }
}

TEST(ImproveFlips, InterfaceBetweenMaterialsIsNotFlipped) {
  TetMesh m = twoTets(0.2, 1, 2);
  m.boundary.push_back({{A, B, C}, 1, 2});  // the interface face abc
  const TetMesh before = m;
  const FlipStats s = improveByFlips(m);
  EXPECT_EQ(s.flips23, 0);
  EXPECT_EQ(m.tets, before.tets);
  EXPECT_EQ(m.tet_materials, before.tet_materials);
}

TEST(ImproveFlips, ConstrainedEdgeIsKept) {
  TetMesh m = threeTets(1.0);
  m.feature_edges = {{E, D}};
  m.feature_edge_curves = {0};
  const FlipStats s = improveByFlips(m);
  EXPECT_EQ(s.flips32, 0);
  EXPECT_TRUE(hasEdge(m, D, E));
}

TEST(ImproveFlips, FlipThatWouldInvertIsRefused) {
  // Apexes off-axis beyond the edge bc: segment de no longer pierces triangle abc, so the 2-3
  // flip would make an inverted tet, although the flat pair would gain from it otherwise.
  TetMesh m = twoTets(0.2);
  m.points[D] = {-1.5, 0, 0.2};
  m.points[E] = {-1.5, 0, -0.2};
  orientAll(m);
  const TetMesh before = m;
  const FlipStats s = improveByFlips(m);
  EXPECT_EQ(s.flips23, 0);
  EXPECT_EQ(m.tets, before.tets);
}

TEST(ImproveFlips, Deterministic) {
  TetMesh a = test::kuhnCube(), b = test::kuhnCube();
  improveByFlips(a);
  improveByFlips(b);
  EXPECT_EQ(a.tets, b.tets);
  TetMesh c = twoTets(0.2), d = twoTets(0.2);
  improveByFlips(c);
  improveByFlips(d);
  EXPECT_EQ(c.tets, d.tets);
}

}  // namespace
}  // namespace oraclemesh
