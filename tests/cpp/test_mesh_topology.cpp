// Boundary extraction, conformity checks and second-order elements (src/core/mesh/Topology,
// SecondOrder) on the Kuhn cube, whose faces, edges and interface are known by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "Error.h"
#include "mesh/Quality.h"
#include "mesh/SecondOrder.h"
#include "mesh/Topology.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"

namespace oraclemesh {
namespace {

Point3 normalOf(const TetMesh& mesh, const BoundaryTriangle& t) {
  return cross(mesh.points[t.v[1]] - mesh.points[t.v[0]], mesh.points[t.v[2]] - mesh.points[t.v[0]]);
}

Point3 centroidOf(const TetMesh& mesh, const BoundaryTriangle& t) {
  return (1.0 / 3) * (mesh.points[t.v[0]] + mesh.points[t.v[1]] + mesh.points[t.v[2]]);
}

const MidNodePlacer kStraight = [](int64_t, int64_t, const Point3& mid) { return mid; };

TEST(MeshTopology, CubeBoundaryIsTwelveOutwardTriangles) {
  const TetMesh cube = test::kuhnCube();
  const std::vector<BoundaryTriangle> boundary = extractBoundary(cube);
  ASSERT_EQ(boundary.size(), 12u);
  double area = 0;
  const Point3 centre{0.5, 0.5, 0.5};
  for (const BoundaryTriangle& t : boundary) {
    EXPECT_EQ(t.material_in, 1);
    EXPECT_EQ(t.material_out, 0);
    const Point3 n = normalOf(cube, t);
    area += 0.5 * norm(n);
    EXPECT_GT(dot(n, centroidOf(cube, t) - centre), 0) << "normal must point out of the cube";
    // Each triangle lies in one cube face: its normal is along one axis.
    EXPECT_NEAR(std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]), norm(n), 1e-12);
  }
  EXPECT_NEAR(area, 6.0, 1e-12);
  // The same faces as the independent check in mesh_checks.h.
  std::set<test::Face> ours;
  for (const BoundaryTriangle& t : boundary) ours.insert(test::sortedFace(t.v[0], t.v[1], t.v[2]));
  const std::vector<test::Face> reference = test::boundaryFaces(cube);
  EXPECT_EQ(ours, std::set<test::Face>(reference.begin(), reference.end()));
}

TEST(MeshTopology, InterfaceBetweenTwoMaterialsIsFoundOnceAndPointsFromSmallerId) {
  const TetMesh cube = test::kuhnCube(/*two_materials=*/true);
  const std::vector<BoundaryTriangle> boundary = extractBoundary(cube);
  ASSERT_EQ(boundary.size(), 14u);  // 12 outer + the 2 triangles of the plane x = y
  std::set<test::Face> interface;
  for (const BoundaryTriangle& t : boundary) {
    if (t.material_out == 0) continue;
    EXPECT_EQ(t.material_in, 1);
    EXPECT_EQ(t.material_out, 2);
    interface.insert(test::sortedFace(t.v[0], t.v[1], t.v[2]));
    // Material 1 is the half x >= y, so the normal from 1 into 2 points towards (-1, 1, 0).
    const Point3 n = normalOf(cube, t);
    EXPECT_NEAR(n[0] / norm(n), -1 / std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(n[1] / norm(n), 1 / std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(n[2], 0, 1e-12);
  }
  EXPECT_EQ(interface, (std::set<test::Face>{{0, 3, 7}, {0, 4, 7}}));
  int outerOfMaterial[3] = {0, 0, 0};
  for (const BoundaryTriangle& t : boundary)
    if (t.material_out == 0) ++outerOfMaterial[t.material_in];
  EXPECT_EQ(outerOfMaterial[1], 6);
  EXPECT_EQ(outerOfMaterial[2], 6);
}

TEST(MeshTopology, InterfaceOrientationFollowsTheSmallerMaterialId) {
  TetMesh cube = test::kuhnCube(/*two_materials=*/true);
  for (int& m : cube.tet_materials) m = m == 1 ? 7 : 3;  // now the half y >= x has the smaller id
  for (const BoundaryTriangle& t : extractBoundary(cube)) {
    if (t.material_out == 0) continue;
    EXPECT_EQ(t.material_in, 3);
    EXPECT_EQ(t.material_out, 7);
    const Point3 n = normalOf(cube, t);
    EXPECT_GT(n[0], 0);  // from y >= x into x >= y
    EXPECT_LT(n[1], 0);
  }
}

TEST(MeshTopology, BoundaryOrderIsDeterministic) {
  const TetMesh cube = test::kuhnCube(true);
  const auto first = extractBoundary(cube), second = extractBoundary(cube);
  ASSERT_EQ(first.size(), second.size());
  for (size_t i = 0; i < first.size(); ++i) EXPECT_EQ(first[i].v, second[i].v);
}

TEST(MeshTopology, CubeIsConforming) {
  for (bool twoMaterials : {false, true}) {
    const ConformityReport c = checkConformity(test::kuhnCube(twoMaterials));
    EXPECT_EQ(c.faces_shared_by_more_than_two, 0);
    EXPECT_EQ(c.open_boundary_edges, 0);
    EXPECT_EQ(c.inverted_tets, 0);
    EXPECT_EQ(c.unused_points, 0);
    EXPECT_EQ(c.inconsistent_mid_nodes, 0);
    EXPECT_TRUE(c.ok());
  }
}

TEST(MeshTopology, InvertedTetIsDetected) {
  TetMesh cube = test::kuhnCube();
  std::swap(cube.tets[4][1], cube.tets[4][2]);
  const ConformityReport c = checkConformity(cube);
  EXPECT_EQ(c.inverted_tets, 1);
  EXPECT_FALSE(c.ok());
  EXPECT_EQ(test::conformity(cube).inverted, 1);  // the independent check agrees
}

TEST(MeshTopology, UnusedPointIsCounted) {
  TetMesh cube = test::kuhnCube();
  cube.points.push_back({5, 5, 5});
  cube.vertex_dimension.push_back(3);
  cube.vertex_curve.push_back(-1);
  const ConformityReport c = checkConformity(cube);
  EXPECT_EQ(c.unused_points, 1);
  EXPECT_FALSE(c.ok());
}

TEST(MeshTopology, FaceOfThreeTetsIsNonManifoldAndLeavesTheBoundaryOpen) {
  // Three tets on the triangle (0, 1, 2), one below and two (overlapping) above. Each edge of
  // the triangle is then in three side faces: an odd count, the region has no closed boundary.
  TetMesh mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1}, {0.2, 0.2, -1}, {0.3, 0.3, 2}};
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  mesh.tet_materials = {1, 1, 1};
  const ConformityReport c = checkConformity(mesh);
  EXPECT_EQ(c.faces_shared_by_more_than_two, 1);
  EXPECT_EQ(c.open_boundary_edges, 3);
  EXPECT_FALSE(c.ok());
  // extractBoundary leaves the broken face out instead of guessing a side.
  for (const BoundaryTriangle& t : extractBoundary(mesh))
    EXPECT_NE(test::sortedFace(t.v[0], t.v[1], t.v[2]), (test::Face{0, 1, 2}));
}

TEST(MeshTopology, RemovingATetKeepsEachMaterialClosed) {
  TetMesh cube = test::kuhnCube(true);
  cube.tets.erase(cube.tets.begin() + 1);
  cube.tet_materials.erase(cube.tet_materials.begin() + 1);
  const ConformityReport c = checkConformity(cube);
  EXPECT_EQ(c.open_boundary_edges, 0);
  EXPECT_TRUE(c.ok());
}

TEST(MeshTopology, CornersThatAreNotIndicesOfPointsAreAnError) {
  TetMesh cube = test::kuhnCube();
  cube.tets[3][2] = -1;
  EXPECT_THROW(extractBoundary(cube), Error);
  EXPECT_THROW(checkConformity(cube), Error);
}

// The final check of every job's mesh: the cube's diagonal 0-7 is an edge of all six tets,
// its face diagonal 1-2 of none (the face z = 0 is split along 0-3).
TEST(MeshTopology, AFeatureEdgeThatIsNoTetEdgeIsAnErrorNamingIt) {
  TetMesh cube = test::kuhnCube();
  cube.feature_edges = {{0, 7}, {7, 3}};
  cube.feature_edge_curves = {0, 0};
  EXPECT_EQ(featureEdgesNotTetEdges(cube), 0);
  EXPECT_NO_THROW(requireFeatureEdgesInTets(cube));
  cube.feature_edges.push_back({1, 2});
  cube.feature_edge_curves.push_back(1);
  size_t first = 99;
  EXPECT_EQ(featureEdgesNotTetEdges(cube, &first), 1);
  EXPECT_EQ(first, 2u);
  EXPECT_EQ(test::featureEdgesNotTetEdges(cube), 1);
  try {
    requireFeatureEdgesInTets(cube);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("1 of 3 feature edges"), std::string::npos) << message;
    EXPECT_NE(message.find("from (1, 0, 0) to (0, 1, 0)"), std::string::npos) << message;
  }
}

TEST(MeshTopology, BoundaryEntriesOfTheWrongLengthAreAnError) {
  TetMesh cube = test::kuhnCube();
  cube.vertex_boundary_entry = {0, 1};
  EXPECT_THROW(extractBoundary(cube), Error);
}

// --- second order ----------------------------------------------------------------------

// Two tets sharing a face, and a third tet of the same material touching them without a face:
// by three nodes not on one line it is held rigidly (one piece, as a cusp's sliver whose faces
// are all boundary); by an edge or by three nodes on one line it hangs (two pieces).
TEST(MeshTopology, PiecesTouchingByThreeNodesOffALineAreOnePiece) {
  TetMesh mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {-1, -1, 2}, {-2, 1, -1}, {2, 2, -2},
                 {0.5, 0, 0}};
  mesh.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  mesh.tet_materials = {1, 1};
  EXPECT_EQ(componentsPerMaterial(mesh), (std::map<int, int64_t>{{1, 1}}));

  TetMesh byThreeNodes = mesh;  // nodes 0, 2 and 4 lie in the two tets, no face of them
  byThreeNodes.tets.push_back({0, 4, 2, 5});
  byThreeNodes.tet_materials.push_back(1);
  EXPECT_EQ(componentsPerMaterial(byThreeNodes), (std::map<int, int64_t>{{1, 1}}));
  byThreeNodes.tet_materials.back() = 2;  // another material's piece is its own
  EXPECT_EQ(componentsPerMaterial(byThreeNodes), (std::map<int, int64_t>{{1, 1}, {2, 1}}));

  TetMesh byAnEdge = mesh;
  byAnEdge.tets.push_back({0, 2, 6, 7});
  byAnEdge.tet_materials.push_back(1);
  EXPECT_EQ(componentsPerMaterial(byAnEdge), (std::map<int, int64_t>{{1, 2}}));

  TetMesh byNodesOnALine = mesh;  // nodes 0, 8 and 1 lie on the x axis
  byNodesOnALine.points[8] = {0.5, 0, 0};
  byNodesOnALine.tets = {{0, 8, 2, 3}, {8, 1, 2, 3}, {0, 8, 6, 7}, {8, 1, 6, 7}};
  byNodesOnALine.tet_materials = {1, 1, 1, 1};
  // The first two share face 8-2-3, the last two face 8-6-7; the pairs share 0, 8, 1 only.
  EXPECT_EQ(componentsPerMaterial(byNodesOnALine), (std::map<int, int64_t>{{1, 2}}));
}

TEST(MeshSecondOrder, OneSharedMidNodePerEdgeInTetEdgeOrder) {
  TetMesh cube = test::kuhnCube(true);
  EXPECT_EQ(makeSecondOrder(cube, kStraight), 0);
  EXPECT_EQ(cube.order(), 2);
  // 12 cube edges + 6 face diagonals + the main diagonal 0-7.
  ASSERT_EQ(cube.points.size(), 8u + 19u);
  ASSERT_EQ(cube.tet_mid_nodes.size(), cube.tets.size());
  for (size_t t = 0; t < cube.tets.size(); ++t)
    for (int e = 0; e < 6; ++e) {
      const Point3& a = cube.points[cube.tets[t][test::kTetEdges[e][0]]];
      const Point3& b = cube.points[cube.tets[t][test::kTetEdges[e][1]]];
      const Point3& mid = cube.points[cube.tet_mid_nodes[t][e]];
      for (int i = 0; i < 3; ++i) EXPECT_EQ(mid[i], 0.5 * (a[i] + b[i])) << "tet " << t << " edge " << e;
    }
  // The first tet's edges are met first, in the order 01, 12, 20, 03, 13, 23.
  for (int e = 0; e < 6; ++e) EXPECT_EQ(cube.tet_mid_nodes[0][e], 8 + e);
  const test::Conformity independent = test::conformity(cube);
  EXPECT_EQ(independent.mid_nodes_not_shared, 0);
  EXPECT_EQ(independent.inverted, 0);
  const ConformityReport c = checkConformity(cube);
  EXPECT_EQ(c.inconsistent_mid_nodes, 0);
  EXPECT_TRUE(c.ok());
  EXPECT_NEAR(measureQuality(cube).volume_per_material.at(1), 0.5, 1e-14);
}

TEST(MeshSecondOrder, MidNodeDimensionsAndCurves) {
  TetMesh cube = test::kuhnCube();
  cube.feature_edges = {{1, 0}};  // the x axis edge, given in reverse order
  cube.feature_edge_curves = {5};
  makeSecondOrder(cube, kStraight);
  const auto mids = test::midNodeOfEdge(cube);
  ASSERT_EQ(mids.size(), 19u);
  for (const auto& [edge, mid] : mids) {
    int expected = 2;  // every cube edge and face diagonal lies on the cube's surface
    if (edge == std::make_pair<int64_t, int64_t>(0, 7)) expected = 3;
    if (edge == std::make_pair<int64_t, int64_t>(0, 1)) expected = 1;
    EXPECT_EQ(cube.vertex_dimension[mid], expected) << edge.first << "-" << edge.second;
    EXPECT_EQ(cube.vertex_curve[mid], expected == 1 ? 5 : -1);
  }
}

TEST(MeshSecondOrder, MidNodesHaveNoRecordedBoundaryEntry) {
  TetMesh cube = test::kuhnCube();
  cube.vertex_boundary_entry.assign(8, 0);
  makeSecondOrder(cube, kStraight);
  ASSERT_EQ(cube.vertex_boundary_entry.size(), cube.points.size());
  for (size_t v = 0; v < cube.points.size(); ++v) EXPECT_EQ(cube.vertex_boundary_entry[v], v < 8 ? 0 : -1);
}

TEST(MeshSecondOrder, WrongMidNodeIsInconsistent) {
  TetMesh cube = test::kuhnCube();
  makeSecondOrder(cube, kStraight);
  // Every tet has the diagonal 0-7 as its edge 03; give tet 1 a node of its own there.
  ASSERT_EQ(cube.tets[1][0], 0);
  ASSERT_EQ(cube.tets[1][3], 7);
  cube.points.push_back(cube.points[cube.tet_mid_nodes[1][3]]);
  cube.vertex_dimension.push_back(3);
  cube.vertex_curve.push_back(-1);
  cube.tet_mid_nodes[1][3] = static_cast<int64_t>(cube.points.size()) - 1;
  const ConformityReport c = checkConformity(cube);
  EXPECT_EQ(c.inconsistent_mid_nodes, 1);
  EXPECT_EQ(c.unused_points, 0);
  EXPECT_FALSE(c.ok());
}

TEST(MeshSecondOrder, FoldedCurvedTetIsInvertedInConformity) {
  TetMesh tet = test::cornerTet();
  makeSecondOrder(tet, kStraight);
  tet.points[tet.tet_mid_nodes[0][0]] = {0.5, 0, 0.3};  // into the tet: det J = 1 - 4 * 0.3 at corner 1
  EXPECT_EQ(checkConformity(tet).inverted_tets, 1);
  EXPECT_EQ(test::conformity(tet).inverted, 1);
}

TEST(MeshSecondOrder, PlacedNodesAreKeptWhenTheyBendGently) {
  // Bulge every boundary mid node of the cube outward by 5% of the edge length: a shape the
  // elements accept, which the volume shows.
  TetMesh cube = test::kuhnCube();
  const Point3 centre{0.5, 0.5, 0.5};
  const auto bulge = [&](int64_t a, int64_t b, const Point3& mid) -> Point3 {
    if (a == 0 && b == 7) return mid;  // the interior diagonal stays straight
    Point3 out = mid - centre;
    for (double& c : out) c = std::fabs(c) > 0.49 ? c : 0;  // only across the faces it lies on
    return mid + (0.05 / norm(out)) * out;
  };
  EXPECT_EQ(makeSecondOrder(cube, bulge), 0);
  const QualityReport q = measureQuality(cube);
  EXPECT_GT(q.volume_per_material.at(1), 1.0);
  EXPECT_NEAR(q.volume_per_material.at(1), test::volumePerMaterial(cube).at(1), 1e-12);
  EXPECT_TRUE(checkConformity(cube).ok());
}

TEST(MeshSecondOrder, PlacementThatWouldFoldFallsBackToStraight) {
  TetMesh tet = test::cornerTet();
  int calls = 0;
  const auto placer = [&](int64_t a, int64_t b, const Point3& mid) -> Point3 {
    ++calls;
    if (a == 0 && b == 1) return {0.5, 0, 0.3};  // folds the tet (det J at corner 1 = -0.2)
    if (a == 0 && b == 2) return {0, 0.5, 0.2};  // det J >= 0.2, 20% of straight: kept
    if (a == 1 && b == 2) return {std::numeric_limits<double>::quiet_NaN(), 0, 0};
    return mid;
  };
  EXPECT_EQ(makeSecondOrder(tet, placer), 2);  // edge 0-1 (fold) and 1-2 (not a number)
  EXPECT_EQ(calls, 8);  // 6 in the first pass, then the 2 refused edges once more (no progress)
  const auto mids = test::midNodeOfEdge(tet);
  EXPECT_EQ(tet.points[mids.at({0, 1})], (Point3{0.5, 0, 0}));
  EXPECT_EQ(tet.points[mids.at({1, 2})], (Point3{0.5, 0.5, 0}));
  EXPECT_EQ(tet.points[mids.at({0, 2})], (Point3{0, 0.5, 0.2}));
  EXPECT_TRUE(checkConformity(tet).ok());
}

TEST(MeshSecondOrder, NearlyFoldedBelowMinimumFractionFallsBack) {
  // det J at corner 2 = 1 - 4 * 0.2498 = 0.0008 of the straight value: positive, still refused.
  TetMesh tet = test::cornerTet();
  const auto placer = [](int64_t a, int64_t b, const Point3& mid) -> Point3 {
    return a == 0 && b == 2 ? Point3{0, 0.5, 0.2498} : mid;
  };
  EXPECT_EQ(makeSecondOrder(tet, placer), 1);
  const auto mids = test::midNodeOfEdge(tet);
  EXPECT_EQ(tet.points[mids.at({0, 2})], (Point3{0, 0.5, 0}));
}

TEST(MeshSecondOrder, SecondCallLeavesTheMeshAlone) {
  TetMesh cube = test::kuhnCube();
  makeSecondOrder(cube, kStraight);
  const size_t points = cube.points.size();
  EXPECT_EQ(makeSecondOrder(cube, kStraight), 0);
  EXPECT_EQ(cube.points.size(), points);
}

}  // namespace
}  // namespace oraclemesh
