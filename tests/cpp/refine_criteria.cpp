// The refiner's cell and facet criteria (T3's and T2's premises) on hand-made tetrahedra and
// facets: no triangulation involved.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "refine/CellCriteria.h"
#include "refine/FacetCriteria.h"

namespace oraclemesh::refine {
namespace {

// A regular tetrahedron of edge 2 sqrt(2), circumradius sqrt(3).
const std::array<Point3, 4> kRegular{Point3{1, 1, 1}, Point3{1, -1, -1}, Point3{-1, 1, -1}, Point3{-1, -1, 1}};
// The corner of the unit cube: shortest edge exactly 1, volume 1/6, so flatness 1.
const std::array<Point3, 4> kCorner{Point3{0, 0, 0}, Point3{1, 0, 0}, Point3{0, 1, 0}, Point3{0, 0, 1}};

MaterialCriteria cellCriteria(double size, double ratio) {
  MaterialCriteria c;
  c.cell_size = size;
  c.cell_radius_edge_ratio = ratio;
  return c;
}

TEST(RefineCellCriteria, RegularTetrahedronMeetsTheCriteria) {
  const CellShape shape = measureCell(kRegular, std::sqrt(3.0));
  EXPECT_NEAR(shape.shortestEdge, 2 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(shape.flatness, 1 / std::sqrt(2.0), 1e-12);  // 0.71, as the refiner's comments say
  const CellVerdict v = CellCriteria(cellCriteria(2, 2)).judge(shape);
  EXPECT_EQ(v.badness, 0);
  EXPECT_FALSE(v.sizeFails);
}

TEST(RefineCellCriteria, FlatTetrahedronIsBadWhateverItsRatio) {
  const std::array<Point3, 4> flat{Point3{0, 0, 0}, Point3{1, 0, 0}, Point3{0, 1, 0}, Point3{1, 1, 1e-6}};
  const CellShape shape = measureCell(flat, 0.75);  // a fine circumradius and radius-edge ratio
  EXPECT_LT(shape.flatness, FlatCellCriterion::kBound);
  const CellVerdict v = CellCriteria(cellCriteria(2, 2)).judge(shape);
  EXPECT_EQ(v.badness, FlatCellCriterion::kExcess);
  EXPECT_TRUE(v.sizeFails);  // redirected like a cell too big, never left by the terminator
  EXPECT_EQ(std::string(v.reason), "flat cell (four nearly coplanar corners)");
  // The corner tetrahedron is far from flat.
  EXPECT_FALSE(FlatCellCriterion::isFlat(flatness(kCorner)));
  EXPECT_DOUBLE_EQ(flatness(kCorner), 1);
}

TEST(RefineCellCriteria, CellSizeBoundIsStrict) {
  const double r = std::sqrt(3.0);
  const CellShape shape = measureCell(kRegular, r);
  EXPECT_EQ(CellCriteria(cellCriteria(r, 0)).judge(shape).badness, 0) << "circumradius equal to cell_size";
  const CellVerdict v = CellCriteria(cellCriteria(r * (1 - 1e-9), 0)).judge(shape);
  EXPECT_GT(v.badness, 1);
  EXPECT_NEAR(v.badness, 1 / (1 - 1e-9), 1e-15);
  EXPECT_TRUE(v.sizeFails);
  EXPECT_EQ(std::string(v.reason), "circumradius above cell_size");
  EXPECT_EQ(CellCriteria(cellCriteria(0, 0)).judge(measureCell(kRegular, 1e9)).badness, 0) << "0 = off";
}

TEST(RefineCellCriteria, RadiusEdgeBoundIsStrictAndNoSizeFailure) {
  // Shortest edge 1: the ratio is the circumradius given.
  const CellShape shape = measureCell(kCorner, 1.5);
  EXPECT_EQ(CellCriteria(cellCriteria(10, 1.5)).judge(shape).badness, 0) << "ratio equal to the bound";
  const CellVerdict v = CellCriteria(cellCriteria(10, 1.25)).judge(shape);
  EXPECT_DOUBLE_EQ(v.badness, 1.5 / 1.25);
  EXPECT_FALSE(v.sizeFails);  // the terminator may leave such a cell next to a small angle
  EXPECT_EQ(std::string(v.reason), "radius-edge ratio above cell_radius_edge_ratio");
  EXPECT_EQ(CellCriteria(cellCriteria(0, 0)).judge(measureCell(kCorner, 100)).badness, 0) << "0 = off";
}

TEST(RefineCellCriteria, WorstFailingCriterionSetsBadness) {
  // Circumradius 3: 3 / 2 beyond cell_size 2, 3 / 1.2 = 2.5 beyond the ratio 1.2.
  const CellVerdict v = CellCriteria(cellCriteria(2, 1.2)).judge(measureCell(kCorner, 3));
  EXPECT_DOUBLE_EQ(v.badness, 3 / 1.2);
  EXPECT_TRUE(v.sizeFails);
  EXPECT_EQ(std::string(v.reason), "radius-edge ratio above cell_radius_edge_ratio");
}

// A right isosceles facet in z = 0 with its circumcentre at (1, 1, 0) and its ball centre
// `height` above it; its smallest angle is 45 degrees.
FacetShape rightFacet(double height, int labelA = 1, int labelB = 0) {
  FacetShape f;
  f.corners = {Point3{0, 0, 0}, Point3{2, 0, 0}, Point3{0, 2, 0}};
  f.ballCentre = {1, 1, height};
  f.labelA = labelA;
  f.labelB = labelB;
  return f;
}

CriteriaTable facetTable(double size, double dist, double angle) {
  CriteriaTable t;
  t.defaults.facet_size = size;
  t.defaults.facet_distance = dist;
  t.defaults.facet_angle = angle;
  return t;
}

TEST(RefineFacetCriteria, GoodFacetAndItsMeasures) {
  const FacetShape f = rightFacet(0.5);
  EXPECT_DOUBLE_EQ(FacetSizeCriterion::ballRadius(f), 1.5);  // sqrt(1 + 1 + 0.25)
  EXPECT_NEAR(FacetDistanceCriterion::distance(f), 0.5, 1e-15);
  EXPECT_NEAR(FacetAngleCriterion::smallestAngleDeg(f), 45, 1e-12);
  const CriteriaTable t = facetTable(2, 1, 25);
  EXPECT_EQ(FacetCriteria(t).judge(f).badness, 0);
}

TEST(RefineFacetCriteria, VertexOffTheBoundaryComesFirst) {
  FacetShape f = rightFacet(0);
  f.cornersOnBoundary = false;
  const CriteriaTable t = facetTable(2, 1, 25);
  const FacetVerdict v = FacetCriteria(t).judge(f);
  EXPECT_EQ(v.badness, FacetOnBoundaryCriterion::kExcess);
  EXPECT_EQ(std::string(v.reason), "a vertex not on the boundary");
}

TEST(RefineFacetCriteria, SizeAndDistanceBoundsAreStrict) {
  const FacetShape f = rightFacet(0.5);  // ball radius 1.5, distance 0.5
  EXPECT_EQ(FacetCriteria(facetTable(1.5, 1, 0)).judge(f).badness, 0) << "ball radius equal to facet_size";
  const CriteriaTable tooBig = facetTable(1.2, 1, 0);
  const FacetVerdict size = FacetCriteria(tooBig).judge(f);
  EXPECT_DOUBLE_EQ(size.badness, 1.5 / 1.2);
  EXPECT_EQ(std::string(size.reason), "surface Delaunay ball radius above facet_size");
  EXPECT_EQ(FacetCriteria(facetTable(10, 0.5, 0)).judge(f).badness, 0) << "distance equal to facet_distance";
  const CriteriaTable tooFar = facetTable(10, 0.25, 0);
  const FacetVerdict dist = FacetCriteria(tooFar).judge(f);
  EXPECT_NEAR(dist.badness, 2, 1e-14);
  EXPECT_EQ(std::string(dist.reason), "facet distance above facet_distance");
}

TEST(RefineFacetCriteria, ThinFacetFailsItsAngleCappedAtThirtyDegrees) {
  FacetShape thin = rightFacet(0);
  thin.corners = {Point3{0, 0, 0}, Point3{2, 0, 0}, Point3{1, std::tan(5 * M_PI / 180), 0}};  // 5, 5, 170 degrees
  thin.ballCentre = {1, -5, 0};
  const CriteriaTable t = facetTable(100, 100, 25);
  const FacetVerdict v = FacetCriteria(t).judge(thin);
  EXPECT_NEAR(v.badness, 25.0 / 5, 1e-9);
  EXPECT_EQ(std::string(v.reason), "facet angle below facet_angle");
  EXPECT_EQ(FacetCriteria(t).judge(thin, false).badness, 0) << "withAngle = false leaves the angle out";
  // A bound of 40 degrees counts as 30 (Mesh_3's cap): 45 degrees pass, 5 fail by 30 / 5.
  const CriteriaTable strict = facetTable(100, 100, 40);
  EXPECT_EQ(FacetCriteria(strict).judge(rightFacet(0)).badness, 0);
  EXPECT_NEAR(FacetCriteria(strict).judge(thin).badness, 30.0 / 5, 1e-9);
}

TEST(RefineFacetCriteria, StrictestMaterialOnEitherSideAndNoneOutside) {
  CriteriaTable t = facetTable(10, 10, 0);
  t.per_material[1] = t.defaults;
  t.per_material[1].facet_size = 1;
  t.per_material[2] = t.defaults;
  t.per_material[2].facet_size = 3;
  const FacetShape between = rightFacet(0.5, 1, 2);  // ball radius 1.5
  EXPECT_DOUBLE_EQ(FacetCriteria(t).bound(between, &MaterialCriteria::facet_size), 1);
  EXPECT_DOUBLE_EQ(FacetCriteria(t).judge(between).badness, 1.5);
  EXPECT_EQ(FacetCriteria(t).judge(rightFacet(0.5, 0, 2)).badness, 0) << "material 2 alone allows 3";
  EXPECT_TRUE(std::isinf(FacetCriteria(t).bound(rightFacet(0.5, 0, 0), &MaterialCriteria::facet_size)));
}

TEST(RefineFacetCriteria, BridgeWiderThanTheContactToleranceIsBad) {
  CriteriaTable t = facetTable(10, 10, 0);  // size and distance pass
  FacetShape between = rightFacet(0.5, 1, 2);
  between.bridge = 0.3;
  EXPECT_EQ(FacetCriteria(t).judge(between).badness, 0) << "contact tolerance 0: not checked";
  t.contact_tolerance = 0.3;
  EXPECT_EQ(FacetCriteria(t).judge(between).badness, 0) << "empty space as wide as the tolerance touches";
  between.bridge = 0.31;
  const FacetVerdict v = FacetCriteria(t).judge(between);
  EXPECT_EQ(v.badness, FacetBridgeCriterion::kExcess);
  EXPECT_EQ(std::string(v.reason), "its dual edge crosses empty space between two parts wider than the contact tolerance");
  // A facet too big by more than the bridge's fixed excess keeps its own reason first.
  const CriteriaTable small = [&] {
    CriteriaTable s = facetTable(0.5, 10, 0);
    s.contact_tolerance = 0.3;
    return s;
  }();
  EXPECT_EQ(std::string(FacetCriteria(small).judge(between).reason), "surface Delaunay ball radius above facet_size");
}

TEST(RefineFacetCriteria, InterfaceCornerOffAPartIsBad) {
  CriteriaTable t = facetTable(10, 10, 0);
  t.contact_tolerance = 0.1;
  FacetShape between = rightFacet(0.5, 1, 2);
  EXPECT_EQ(FacetCriteria(t).judge(between).badness, 0) << "every corner touches both parts";
  between.offInterface = true;  // a corner on a chamfer below the plate it is said to touch
  const FacetVerdict v = FacetCriteria(t).judge(between);
  EXPECT_EQ(v.badness, FacetOnInterfaceCriterion::kExcess);
  EXPECT_EQ(std::string(v.reason), "a corner farther than the contact tolerance from one of the two parts it lies between");
  t.contact_tolerance = 0;
  EXPECT_EQ(FacetCriteria(t).judge(between).badness, 0) << "contact tolerance 0: not checked";
}

TEST(RefineFacetCriteria, FacetAcrossASmallDihedralEdgeIsBadWhenDeeperThanHalfTheFacetDistance) {
  FacetShape across = rightFacet(0.5);  // facet distance measure 0.5
  EXPECT_EQ(FacetCriteria(facetTable(10, 0.9, 0)).judge(across).badness, 0) << "corners on one face";
  across.acrossSharpEdge = true;
  EXPECT_EQ(FacetCriteria(facetTable(10, 1, 0)).judge(across).badness, 0) << "depth 0.5 is half of 1: a chord of the tip";
  const FacetVerdict deep = FacetCriteria(facetTable(10, 0.9, 0)).judge(across);
  EXPECT_EQ(deep.badness, FacetAcrossSharpEdgeCriterion::kExcess) << "0.5 deeper than 0.45, within facet_distance 0.9";
  EXPECT_EQ(std::string(deep.reason),
            "it spans the wedge beside a dihedral angle under 60 degrees deeper than half the facet distance");
  EXPECT_EQ(FacetCriteria(facetTable(10, 0, 0)).judge(across).badness, FacetAcrossSharpEdgeCriterion::kExcess)
      << "no facet distance: every facet across the edge is bad";
  // A facet farther than its facet distance keeps that reason when it is the worse.
  EXPECT_EQ(std::string(FacetCriteria(facetTable(10, 0.1, 0)).judge(across).reason),
            "facet distance above facet_distance");
}

}  // namespace
}  // namespace oraclemesh::refine
