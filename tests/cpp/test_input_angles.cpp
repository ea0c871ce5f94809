// The small-input-angle report: dihedral angles along feature edges, angles between feature
// curves at shared vertices and cone apexes, only where they are on the composite boundary.
#include <BRepPrimAPI_MakeBox.hxx>
#include <gtest/gtest.h>

#include <cmath>

#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"
#include "features/BrepSharpEdges.h"
#include "features/CoincidentFeatures.h"
#include "features/InputAngles.h"
#include "small_angle_shapes.h"

namespace oraclemesh {
namespace {

struct Composition {
  std::unique_ptr<HierarchicalOracle> oracle;
  FeatureGraph features;
};

// Entries in priority order, each a material of its own; features as the pipeline builds them.
Composition compose(const std::vector<std::pair<TopoDS_Shape, std::string>>& shapes) {
  std::vector<OracleEntry> entries;
  for (size_t i = 0; i < shapes.size(); ++i)
    entries.push_back({std::make_shared<BrepSolid>(shapes[i].first, shapes[i].second), Role::Material,
                       static_cast<int>(i) + 1});
  Composition c;
  c.oracle = std::make_unique<HierarchicalOracle>(entries);
  FeatureGraph all;
  for (size_t i = 0; i < entries.size(); ++i) {
    const FeatureGraph g =
        extractSharpEdges(static_cast<const BrepSolid&>(*entries[i].source), static_cast<int>(i), 30, 1.0);
    all.polylines.insert(all.polylines.end(), g.polylines.begin(), g.polylines.end());
  }
  c.features = removeCoincidentFeatures(clipToCompositeBoundary(all, *c.oracle), *c.oracle);
  return c;
}

TEST(InputAngles, BoxHasNone) {
  const Composition c = compose({{BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "box"}});
  EXPECT_TRUE(findSmallInputAngles(*c.oracle, c.features, 60).empty());
}

TEST(InputAngles, WedgeReportsItsDihedralAndCurveAngles) {
  const Composition c = compose({{test::wedge(10, 20, 5), "wedge"}});
  const auto angles = findSmallInputAngles(*c.oracle, c.features, 60);
  int dihedral = 0, curves = 0;
  for (const SmallInputAngle& a : angles) {
    EXPECT_NEAR(a.angle_deg, 10, 1e-6) << a.kind;
    EXPECT_EQ(a.input, "wedge");
    // Everything small is on the edge through the origin (x = y = 0).
    EXPECT_NEAR(a.location[0], 0, 1e-9);
    EXPECT_NEAR(a.location[1], 0, 1e-9);
    dihedral += a.kind == "dihedral";
    curves += a.kind == "curves";
  }
  EXPECT_EQ(dihedral, 1);  // the edge along z
  EXPECT_EQ(curves, 2);    // bottom and top triangle corners
}

TEST(InputAngles, ConeTipReportedUnlessBuried) {
  const double radius = 2, height = 10;
  const double opening = 2 * std::atan(radius / height) / test::kDegree;
  {
    const Composition c = compose({{test::coneWithTip(gp_Pnt(0, 0, 0), radius, height), "cone"}});
    const auto angles = findSmallInputAngles(*c.oracle, c.features, 60);
    ASSERT_EQ(angles.size(), 1u);
    EXPECT_EQ(angles[0].kind, "cone_apex");
    EXPECT_NEAR(angles[0].angle_deg, opening, 1e-9);
    EXPECT_NEAR(angles[0].location[2], height, 1e-9);
  }
  {  // The tip buried in a higher-priority box is no input angle of the composite domain.
    const TopoDS_Shape cap = BRepPrimAPI_MakeBox(gp_Pnt(-5, -5, 8), 10, 10, 5).Shape();
    const Composition c = compose({{cap, "cap"}, {test::coneWithTip(gp_Pnt(0, 0, 0), radius, height), "cone"}});
    for (const SmallInputAngle& a : findSmallInputAngles(*c.oracle, c.features, 60)) EXPECT_NE(a.kind, "cone_apex");
  }
}

TEST(InputAngles, ReentrantEdgesAreNotSmall) {
  // An L-shaped block of two overlapping boxes has 270-degree edges and shared edges: nothing
  // to report once coincident features are merged, as the pipeline does.
  const Composition c = compose({{BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10, 4, 4).Shape(), "foot"},
                                 {BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 4, 4, 10).Shape(), "leg"}});
  EXPECT_TRUE(findSmallInputAngles(*c.oracle, c.features, 60).empty());
}

}  // namespace
}  // namespace oraclemesh
