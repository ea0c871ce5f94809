// Flat caps (src/core/improve/FlatCaps) on a hand-built square pyramid: the square
// p0 p1 p2 p3 on top, the apex q below; the pyramid is the two tets under the diagonal p1 p3,
// and on top of them lies the flat tet p0 p1 p2 p3 whose diagonal p0 p2 is `lift` above (its
// two top faces on the boundary, or on an interface with a second pyramid above, apex r).
#include <gtest/gtest.h>

#include <algorithm>

#include "RunControl.h"
#include "improve/FlatCaps.h"
#include "improve/MeshImprovement.h"
#include "improve/TetShape.h"
#include "mesh/Topology.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"

namespace oraclemesh {
namespace {

constexpr int64_t P0 = 0, P1 = 1, P2 = 2, P3 = 3, Q = 4, R = 5;
constexpr double kFlatness = 1e-9;  // absolute: the pyramids' diagonal is about 2
constexpr double kVolumeBound = 1e-9;

// Every tet positive, the boundary listed, every vertex on a surface and on no curve.
void finish(TetMesh& m) {
  for (auto& t : m.tets)
    if (test::orientation(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) < 0) std::swap(t[0], t[1]);
  m.boundary = extractBoundary(m);
  m.vertex_dimension.assign(m.points.size(), 2);
  m.vertex_curve.assign(m.points.size(), -1);
}

// `above` = 0: nothing above the cap; else a second pyramid of that material.
TetMesh cappedPyramid(double lift, int above = 0) {
  TetMesh m;
  m.points = {{0, 0, lift}, {1, 0, 0}, {1, 1, lift}, {0, 1, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}};
  m.tets = {{P0, P1, P3, Q}, {P2, P1, P3, Q}, {P0, P1, P2, P3}};
  m.tet_materials = {1, 1, 1};
  if (above != 0) {
    m.tets.push_back({P0, P1, P2, R});
    m.tets.push_back({P0, P2, P3, R});
    m.tet_materials.push_back(above);
    m.tet_materials.push_back(above);
  } else {
    m.points.pop_back();
  }
  finish(m);
  return m;
}

bool hasEdge(const TetMesh& m, int64_t u, int64_t v) {
  for (const auto& t : m.tets)
    if (std::count(t.begin(), t.end(), u) && std::count(t.begin(), t.end(), v)) return true;
  return false;
}

double minDihedralOf(const TetMesh& m) {
  double lo = 180;
  for (const auto& t : m.tets) lo = std::min(lo, smallestDihedral(m.points, t));
  return lo;
}

// Positive tets, closed material boundaries, mesh.boundary as extractBoundary gives it, each
// material's volume within `bound` of before, every feature edge a tet edge.
void expectConsistent(const TetMesh& before, const TetMesh& after, double bound) {
  for (const auto& t : after.tets)
    EXPECT_GT(test::orientation(after.points[t[0]], after.points[t[1]], after.points[t[2]], after.points[t[3]]), 0);
  const ConformityReport c = checkConformity(after);
  EXPECT_EQ(c.open_boundary_edges, 0);
  EXPECT_EQ(c.faces_shared_by_more_than_two, 0);
  EXPECT_EQ(test::listedBoundaryFaces(after), test::boundaryFaces(after));
  const auto vb = test::volumePerMaterial(before), va = test::volumePerMaterial(after);
  for (const auto& [material, volume] : vb) EXPECT_NEAR(va.at(material), volume, bound * volume) << material;
  EXPECT_EQ(test::featureEdgesNotTetEdges(after), 0);
}

TEST(ImproveFlatCaps, CapOnAPlaneIsRemovedAndTheTopStaysClosedAndPlanar) {
  const TetMesh before = cappedPyramid(1e-12);
  ASSERT_LT(minDihedralOf(before), 1e-6);
  TetMesh m = before;
  const FlatCapStats s = removeFlatCaps(m, kFlatness, kVolumeBound);
  EXPECT_EQ(s.boundary_caps_removed, 1);
  EXPECT_EQ(s.caps_kept, 0);
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_FALSE(hasEdge(m, P0, P2));
  EXPECT_GT(minDihedralOf(m), 10);
  EXPECT_GT(s.largest_volume_change, 0);
  EXPECT_LE(s.largest_volume_change, kVolumeBound);
  expectConsistent(before, m, kVolumeBound);
  // The top of the boundary is the other triangulation of the square, its normals up.
  int top = 0;
  for (const BoundaryTriangle& b : m.boundary) {
    if (std::count(b.v.begin(), b.v.end(), Q)) continue;
    ++top;
    const Point3 n = cross(m.points[b.v[1]] - m.points[b.v[0]], m.points[b.v[2]] - m.points[b.v[0]]);
    EXPECT_GT(n[2], 0);
    EXPECT_NEAR(std::abs(n[0]) + std::abs(n[1]), 0, 1e-11);
  }
  EXPECT_EQ(top, 2);
}

TEST(ImproveFlatCaps, CapCarryingAFeatureEdgeNoOtherTetHasIsKept) {
  TetMesh m = cappedPyramid(1e-12);
  m.feature_edges = {{P0, P2}};
  m.feature_edge_curves = {0};
  const FlatCapStats s = removeFlatCaps(m, kFlatness, kVolumeBound);
  EXPECT_EQ(s.boundary_caps_removed, 0);
  EXPECT_EQ(s.caps_kept, 1);
  EXPECT_EQ(m.tets.size(), 3u);
  EXPECT_TRUE(hasEdge(m, P0, P2));
}

TEST(ImproveFlatCaps, CapOnACurvedPatchIsKept) {
  const TetMesh before = cappedPyramid(1e-3);  // a ridge of 1e-3 across the square: not one plane
  TetMesh m = before;
  const FlatCapStats s = removeFlatCaps(m, kFlatness, kVolumeBound);
  EXPECT_EQ(s.boundary_caps_removed + s.interface_caps_flipped + s.caps_kept, 0);
  EXPECT_EQ(m.tets, before.tets);
}

// With curved caps allowed, the same ridge (1e-3 over a diagonal of 1.4: within 1 % of the
// longest edge) is a sliver on a curved piece: it goes, and its volume counts apart.
TEST(ImproveFlatCaps, CapOnACurvedPatchGoesWhenCurvedCapsAreAllowed) {
  const TetMesh before = cappedPyramid(1e-3);
  TetMesh m = before;
  const FlatCapStats s = removeFlatCaps(m, kFlatness, kVolumeBound, CurvedCapLimits{0.01, 1e-2});
  EXPECT_EQ(s.boundary_caps_removed, 1);
  EXPECT_EQ(s.curved_caps, 1);
  EXPECT_EQ(s.largest_volume_change, 0);
  // What moved is the cap's volume (1e-3 / 3, a share of 1e-3 of the material's).
  const double share = (test::volumePerMaterial(before).at(1) - test::volumePerMaterial(m).at(1)) /
                       test::volumePerMaterial(before).at(1);
  EXPECT_GT(share, 0);
  EXPECT_NEAR(s.largest_curved_volume_change, share, 1e-12);
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_FALSE(hasEdge(m, P0, P2));
  expectConsistent(before, m, 1e-2);
}

TEST(ImproveFlatCaps, CurvedCapOverItsVolumeBoundOrFlatnessIsKept) {
  for (const CurvedCapLimits limits : {CurvedCapLimits{0.01, 1e-4}, CurvedCapLimits{1e-4, 1e-2}}) {
    TetMesh m = cappedPyramid(1e-3);
    const FlatCapStats s = removeFlatCaps(m, kFlatness, kVolumeBound, limits);
    EXPECT_EQ(s.boundary_caps_removed, 0);
    EXPECT_EQ(m.tets.size(), 3u);
  }
}

TEST(ImproveFlatCaps, CapOverTheVolumeBoundIsKept) {
  TetMesh m = cappedPyramid(1e-12);
  const FlatCapStats s = removeFlatCaps(m, kFlatness, 1e-13);  // the cap is 1e-12 of the volume
  EXPECT_EQ(s.boundary_caps_removed, 0);
  EXPECT_EQ(s.caps_kept, 1);
  EXPECT_EQ(m.tets.size(), 3u);
}

TEST(ImproveFlatCaps, CapOnAnInterfaceIsFlippedOnBothSides) {
  const TetMesh before = cappedPyramid(1e-12, 2);
  TetMesh m = before;
  const FlatCapStats s = removeFlatCaps(m, kFlatness, kVolumeBound);
  EXPECT_EQ(s.interface_caps_flipped, 1);
  EXPECT_EQ(s.boundary_caps_removed, 0);
  ASSERT_EQ(m.tets.size(), 4u);  // the 3-2 flip of the ring around p0 p2, all of material 2
  EXPECT_FALSE(hasEdge(m, P0, P2));
  EXPECT_EQ(std::count(m.tet_materials.begin(), m.tet_materials.end(), 1), 2);
  EXPECT_GT(minDihedralOf(m), 10);
  expectConsistent(before, m, kVolumeBound);
  // The interface is the square's other triangulation.
  int interface = 0;
  for (const BoundaryTriangle& b : m.boundary)
    if (b.material_out == 2) {
      ++interface;
      EXPECT_TRUE(std::count(b.v.begin(), b.v.end(), P1) && std::count(b.v.begin(), b.v.end(), P3));
    }
  EXPECT_EQ(interface, 2);
}

// A fold, as screw.step's chamfer had them: the flat tet p0 p1 p2 p3 (p2 `lift` above the
// plane of the others) stands on one tet under p0 p1 p3 alone, so three of its faces are on
// the boundary: its top (p0 p1 p2, p0 p2 p3) and, facing down, p1 p2 p3. With `wing`, a tet
// hanging from edge p1 p2 keeps p2 in the mesh once the fold is gone.
constexpr int64_t E = 5, F = 6;

TetMesh foldOnATet(double lift, bool wing) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, lift}, {0, 1, 0}, {0.3, 0.3, -1}, {2, 0, 0}, {2, 1, 1}};
  m.tets = {{P0, P1, P3, Q}, {P0, P1, P2, P3}};
  if (wing) m.tets.push_back({P1, P2, E, F});
  else m.points.resize(5);
  m.tet_materials.assign(m.tets.size(), 1);
  finish(m);
  return m;
}

TEST(ImproveFlatCaps, FoldOnTheOuterBoundaryIsTakenOut) {
  const TetMesh before = foldOnATet(1e-12, true);
  ASSERT_LT(minDihedralOf(before), 1e-6);
  TetMesh m = before;
  const FlatCapStats s = removeFlatCaps(m, kFlatness, kVolumeBound);
  EXPECT_EQ(s.folds_removed, 1);
  EXPECT_EQ(s.caps_kept, 0);
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_FALSE(hasEdge(m, P0, P2));
  EXPECT_FALSE(hasEdge(m, P2, P3));
  EXPECT_TRUE(hasEdge(m, P1, P2));
  EXPECT_GT(minDihedralOf(m), 10);
  expectConsistent(before, m, kVolumeBound);
  // The fold's inner face is boundary now, and no boundary face has a corner at p2 but the wing's.
  const auto faces = test::listedBoundaryFaces(m);
  EXPECT_TRUE(std::binary_search(faces.begin(), faces.end(), test::sortedFace(P0, P1, P3)));
  for (const BoundaryTriangle& b : m.boundary)
    if (std::count(b.v.begin(), b.v.end(), P2)) EXPECT_TRUE(std::count(b.v.begin(), b.v.end(), E) || std::count(b.v.begin(), b.v.end(), F));
}

TEST(ImproveFlatCaps, FoldIsKeptWhenItsCornerOrAFeatureEdgeWouldGo) {
  TetMesh alone = foldOnATet(1e-12, false);  // p2 is in no other tet
  FlatCapStats s = removeFlatCaps(alone, kFlatness, kVolumeBound);
  EXPECT_EQ(s.folds_removed, 0);
  EXPECT_EQ(s.caps_kept, 1);
  EXPECT_EQ(alone.tets.size(), 2u);

  TetMesh feature = foldOnATet(1e-12, true);  // p0 p2 is a feature edge only the fold has
  feature.feature_edges = {{P0, P2}};
  feature.feature_edge_curves = {0};
  s = removeFlatCaps(feature, kFlatness, kVolumeBound);
  EXPECT_EQ(s.folds_removed, 0);
  EXPECT_EQ(feature.tets.size(), 3u);
  EXPECT_TRUE(hasEdge(feature, P0, P2));

  TetMesh steep = foldOnATet(1e-3, true);  // not flat: a corner of the part, not a fold
  s = removeFlatCaps(steep, kFlatness, kVolumeBound);
  EXPECT_EQ(s.folds_removed + s.caps_kept, 0);
  EXPECT_EQ(steep.tets.size(), 3u);
}

TEST(ImproveFlatCaps, TheStageRunsThemFirstAndReportsThem) {
  TetMesh m = cappedPyramid(1e-12);
  const ImprovementStats s = improveMesh(m, ImprovementOptions{}, RunControl());
  EXPECT_EQ(s.flat_caps.boundary_caps_removed, 1);
  EXPECT_LT(s.min_dihedral_before, 1e-6);
  EXPECT_GT(s.min_dihedral_after, 10);
  EXPECT_EQ(m.boundary.size(), extractBoundary(m).size());
}

}  // namespace
}  // namespace oraclemesh
