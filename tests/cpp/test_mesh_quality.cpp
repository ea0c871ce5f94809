// Shape measures and the quality report of src/core/mesh/Quality, checked against values
// known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>

#include "Error.h"
#include "mesh/Quality.h"
#include "mesh/SecondOrder.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"

namespace oraclemesh {
namespace {

const double kRegularDihedral = std::acos(1.0 / 3.0) * 180.0 / M_PI;  // 70.5288 degrees

// Regular tet with edge length 2 sqrt(2): alternate corners of the cube [-1,1]^3.
struct RegularTet {
  Point3 a{1, 1, 1}, b{1, -1, -1}, c{-1, -1, 1}, d{-1, 1, -1};
};

TEST(MeshQuality, RegularTetHasAllDihedralAnglesArccosOneThird) {
  const RegularTet t;
  ASSERT_GT(test::orientation(t.a, t.b, t.c, t.d), 0);
  EXPECT_NEAR(kRegularDihedral, 70.5288, 1e-4);
  for (double angle : dihedralAngles(t.a, t.b, t.c, t.d)) EXPECT_NEAR(angle, kRegularDihedral, 1e-10);
}

TEST(MeshQuality, RegularTetVolumeAndRadiusEdgeRatio) {
  const RegularTet t;
  const double edge = 2 * std::sqrt(2.0);
  EXPECT_NEAR(tetVolume(t.a, t.b, t.c, t.d), edge * edge * edge / (6 * std::sqrt(2.0)), 1e-12);
  EXPECT_NEAR(tetVolume(t.a, t.b, t.c, t.d), 8.0 / 3.0, 1e-12);  // cube 8 minus four corners of 4/3
  EXPECT_NEAR(radiusEdgeRatio(t.a, t.b, t.c, t.d), std::sqrt(6.0) / 4, 1e-12);
}

TEST(MeshQuality, CornerTetAnglesInEdgeOrder) {
  const Point3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  // Edges 01, 20, 03 lie on the coordinate axes, where two coordinate planes meet at 90
  // degrees; the others meet the slanted face x + y + z = 1 at acos(1/sqrt(3)).
  const double slanted = std::acos(1 / std::sqrt(3.0)) * 180 / M_PI;
  const std::array<double, 6> expected{90, slanted, 90, 90, slanted, slanted};
  const std::array<double, 6> angles = dihedralAngles(o, x, y, z);
  for (int e = 0; e < 6; ++e) EXPECT_NEAR(angles[e], expected[e], 1e-10) << "edge " << e;
  EXPECT_NEAR(tetVolume(o, x, y, z), 1.0 / 6, 1e-15);
  // Circumcentre (1/2, 1/2, 1/2), shortest edge 1.
  EXPECT_NEAR(radiusEdgeRatio(o, x, y, z), std::sqrt(3.0) / 2, 1e-12);
}

TEST(MeshQuality, SwappingTwoCornersNegatesVolumeButKeepsAngles) {
  const RegularTet t;
  EXPECT_NEAR(tetVolume(t.b, t.a, t.c, t.d), -8.0 / 3.0, 1e-12);
  for (double angle : dihedralAngles(t.b, t.a, t.c, t.d)) EXPECT_NEAR(angle, kRegularDihedral, 1e-10);
}

TEST(MeshQuality, FlatTetHasInfiniteRadiusEdgeAndZeroOr180Angles) {
  const Point3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0}, d{1, 1, 0};
  EXPECT_EQ(tetVolume(a, b, c, d), 0);
  EXPECT_TRUE(std::isinf(radiusEdgeRatio(a, b, c, d)));
  for (double angle : dihedralAngles(a, b, c, d)) EXPECT_TRUE(angle < 1e-9 || angle > 180 - 1e-9) << angle;
}

TEST(MeshQuality, SliverHasSmallDihedralAngle) {
  // Four nearly coplanar points on a square: the classic sliver, fine radius-edge ratio but
  // dihedral angles near 0 and 180.
  const Point3 a{0, 0, 0}, b{1, 0, 0.01}, c{1, 1, 0}, d{0, 1, 0.01};
  const auto angles = dihedralAngles(a, b, c, d);
  EXPECT_LT(*std::min_element(angles.begin(), angles.end()), 3);
  EXPECT_GT(*std::max_element(angles.begin(), angles.end()), 177);
  EXPECT_LT(radiusEdgeRatio(a, b, c, d), 1);
}

TEST(MeshQuality, KuhnCubeReport) {
  const TetMesh cube = test::kuhnCube(/*two_materials=*/true, /*size=*/2.0);
  const QualityReport q = measureQuality(cube);
  // Every Kuhn tet has the dihedral angles 45, 45, 60, 90, 90, 90.
  EXPECT_NEAR(q.min_dihedral, 45, 1e-9);
  EXPECT_NEAR(q.max_dihedral, 90, 1e-9);
  EXPECT_NEAR(q.max_radius_edge, std::sqrt(3.0) / 2, 1e-12);
  EXPECT_NEAR(q.mean_radius_edge, std::sqrt(3.0) / 2, 1e-12);
  ASSERT_EQ(q.min_dihedral_histogram.size(), 18u);
  EXPECT_EQ(q.min_dihedral_histogram[4], 6);  // [40, 50)
  EXPECT_EQ(std::accumulate(q.min_dihedral_histogram.begin(), q.min_dihedral_histogram.end(), 0), 6);
  EXPECT_EQ(q.inverted, 0);
  ASSERT_EQ(q.tets_per_material.size(), 2u);
  EXPECT_EQ(q.tets_per_material.at(1), 3);
  EXPECT_EQ(q.tets_per_material.at(2), 3);
  EXPECT_NEAR(q.volume_per_material.at(1), 4.0, 1e-12);  // half of the 2 x 2 x 2 cube
  EXPECT_NEAR(q.volume_per_material.at(2), 4.0, 1e-12);
}

TEST(MeshQuality, InvertedTetIsCounted) {
  TetMesh cube = test::kuhnCube();
  std::swap(cube.tets[2][0], cube.tets[2][1]);
  const QualityReport q = measureQuality(cube);
  EXPECT_EQ(q.inverted, 1);
  EXPECT_NEAR(q.volume_per_material.at(1), 1.0 - 2.0 / 6, 1e-12);  // the inverted tet counts -1/6
}

TEST(MeshQuality, EmptyMeshGivesZeros) {
  const QualityReport q = measureQuality(TetMesh{});
  EXPECT_EQ(q.min_dihedral, 0);
  EXPECT_EQ(q.max_dihedral, 0);
  EXPECT_EQ(q.inverted, 0);
  EXPECT_TRUE(q.tets_per_material.empty());
}

TEST(MeshQuality, MismatchedArraysAreRefusedNotRead) {
  TetMesh cube = test::kuhnCube();
  cube.tets[0][3] = 99;  // no such point
  EXPECT_THROW(measureQuality(cube), Error);
  TetMesh noMaterials = test::kuhnCube();
  noMaterials.tet_materials.pop_back();
  EXPECT_THROW(measureQuality(noMaterials), Error);
}

Tet10Nodes straightTet10(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  Tet10Nodes n{a, b, c, d};
  for (int e = 0; e < 6; ++e) n[4 + e] = 0.5 * (n[kTetEdgeCorners[e][0]] + n[kTetEdgeCorners[e][1]]);
  return n;
}

TEST(MeshQuality, StraightTet10JacobianIsSixTimesVolumeEverywhere) {
  const RegularTet t;
  const Tet10Nodes n = straightTet10(t.a, t.b, t.c, t.d);
  for (const std::array<double, 4>& l : {std::array<double, 4>{1, 0, 0, 0}, std::array<double, 4>{0, 0, 0, 1},
                                         std::array<double, 4>{0.1, 0.2, 0.3, 0.4}})
    EXPECT_NEAR(tet10JacobianDeterminant(n, l), 16.0, 1e-12);
  EXPECT_NEAR(tet10MinJacobianAtCornersAndGaussPoints(n), 16.0, 1e-12);
}

// Pushing the mid node of edge 01 of the corner tet to (1/2, 0, -delta) maps z to
// zeta - 4 delta l0 l1, so det J = 1 + 4 delta xi and the volume is (1 + delta) / 6 exactly.
TetMesh cornerTetWithBentEdge(double delta) {
  TetMesh mesh = test::cornerTet();
  makeSecondOrder(mesh, [](int64_t, int64_t, const Point3& mid) { return mid; });
  mesh.points[mesh.tet_mid_nodes[0][0]] = {0.5, 0, -delta};
  return mesh;
}

TEST(MeshQuality, CurvedTet10VolumeIsExact) {
  for (double delta : {0.0, 0.1, -0.2}) {
    const TetMesh mesh = cornerTetWithBentEdge(delta);
    EXPECT_NEAR(elementVolume(mesh, 0), (1 + delta) / 6, 1e-14) << delta;
    EXPECT_NEAR(test::tetVolume(mesh, 0), (1 + delta) / 6, 1e-14) << delta;  // independent rule
    EXPECT_NEAR(measureQuality(mesh).volume_per_material.at(1), (1 + delta) / 6, 1e-14);
    // det J at corner 1 (xi = 1) is 1 + 4 delta, elsewhere among the samples larger or 1.
    EXPECT_NEAR(tet10MinJacobianAtCornersAndGaussPoints(tet10Nodes(mesh, 0)), std::min(1.0, 1 + 4 * delta), 1e-14);
  }
}

// Mid nodes moved so that the determinant stays positive at the corners and the centroid but
// not at the first integration point of C3D10 (found by a random search): CalculiX would stop
// there, so the check must see it.
TEST(MeshQuality, Tet10FoldedOnlyAtAnIntegrationPointHasNegativeJacobian) {
  Tet10Nodes n{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-0.257, -0.159, 0.21}, {0.203, 0.504, -0.216},
                {-0.064, 0.402, -0.287}, {0.159, -0.316, 0.25}, {0.718, 0.239, 0.662}, {0.081, 1.065, 0.193}}};
  for (const std::array<double, 4>& l :
       {std::array<double, 4>{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}, {0.25, 0.25, 0.25, 0.25}})
    EXPECT_GT(tet10JacobianDeterminant(n, l), 0.01);
  const double a = 0.5854101966249685, b = 0.1381966011250105;
  EXPECT_NEAR(tet10JacobianDeterminant(n, {a, b, b, b}), -1.2048, 1e-4);
  EXPECT_LT(tet10MinJacobianAtCornersAndGaussPoints(n), 0);
}

TEST(MeshQuality, FoldedTet10HasNegativeJacobian) {
  const TetMesh mesh = cornerTetWithBentEdge(-0.3);
  EXPECT_NEAR(tet10JacobianDeterminant(tet10Nodes(mesh, 0), {0, 1, 0, 0}), -0.2, 1e-14);
  EXPECT_LT(tet10MinJacobianAtCornersAndGaussPoints(tet10Nodes(mesh, 0)), 0);
  // The corners alone are fine: measureQuality's `inverted` is about corners only.
  EXPECT_EQ(measureQuality(mesh).inverted, 0);
}

}  // namespace
}  // namespace oraclemesh
