// The small-input-angle report: dihedral angles along feature edges, angles between feature
// curves at shared vertices and cone apexes, only where they are on the composite boundary.
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>
#include <gtest/gtest.h>

#include <cmath>

#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"
#include "features/BrepSharpEdges.h"
#include "features/CoincidentFeatures.h"
#include "features/InputAngles.h"
#include "features/JunctionCurves.h"
#include "small_angle_shapes.h"

namespace oraclemesh {
namespace {

struct Composition {
  std::unique_ptr<HierarchicalOracle> oracle;
  FeatureGraph features;
  std::unique_ptr<JunctionCurves> junctions;  // with junctions only
};

// Entries in priority order, each a material of its own; features as the pipeline builds them.
Composition compose(const std::vector<std::pair<TopoDS_Shape, std::string>>& shapes, bool junctions = false) {
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
  FeatureGraph clipped = clipToCompositeBoundary(all, *c.oracle);
  if (junctions) {
    c.junctions = std::make_unique<JunctionCurves>(JunctionCurves::compute(*c.oracle));
    clipped = joinJunctions(clipped, c.junctions->polylines(1.0), *c.oracle, *c.junctions);
  }
  c.features = removeCoincidentFeatures(clipped, *c.oracle);
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

TEST(InputAngles, CurveAnglesComeFromTheExactTangents) {
  // A 20-degree corner between a line and an arc (radius 14.6 over a 10 mm chord), sampled
  // coarsely (edge size 1 gives 11 chords of 1.8 degrees each along the arc): the first chord
  // alone would give 19.1 degrees; the exact tangents give 20.
  const double angle = 20;
  const Composition c = compose({{test::circularSegment(angle, 10, 5), "segment"}});
  const auto angles = findSmallInputAngles(*c.oracle, c.features, 60);
  int curves = 0, dihedral = 0;
  for (const SmallInputAngle& a : angles) {
    EXPECT_NEAR(a.angle_deg, angle, 1e-9) << a.kind;
    // Both chord ends, bottom (z = 0) and top (z = 5): x is 0 or 10, y is 0.
    EXPECT_NEAR(std::min(std::abs(a.location[0]), std::abs(a.location[0] - 10)), 0, 1e-9);
    EXPECT_NEAR(a.location[1], 0, 1e-9);
    curves += a.kind == "curves";
    dihedral += a.kind == "dihedral";
  }
  EXPECT_EQ(curves, 4) << "two corners on each of the top and bottom faces";
  EXPECT_EQ(dihedral, 2) << "the vertical edges at the chord ends";
  // The bottom arc's first chord makes a clearly smaller angle with the line than its tangent.
  int bottomArcs = 0;
  for (const FeaturePolyline& pl : c.features.polylines) {
    const Point3 first = pl.points[1] - pl.points[0];
    if (std::abs(pl.points[0][2]) > 1e-9 || std::abs(first[2]) > 1e-9 || std::abs(first[1]) < 1e-9) continue;
    ++bottomArcs;
    EXPECT_LT(std::atan2(std::abs(first[1]), std::abs(first[0])) / test::kDegree, angle - 0.5);
  }
  EXPECT_EQ(bottomArcs, 1);
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

// A pin (priority) entering a 100 x 60 x 10 plate's top face with its axis at `angleDeg` to
// the face, ending inside the plate.
Composition pinEnteringPlate(double angleDeg) {
  // The axis runs from 4 above the face to 4 below it: the pin's ends stay clear of the face
  // and of the plate's bottom.
  const double a = angleDeg * test::kDegree, length = 8 / std::sin(a);
  const gp_Pnt start(10, 30, 14);
  const TopoDS_Shape pin =
      BRepPrimAPI_MakeCylinder(gp_Ax2(start, gp_Dir(std::cos(a), 0, -std::sin(a))), 3, length).Shape();
  return compose({{pin, "pin"}, {BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 100, 60, 10).Shape(), "plate"}}, true);
}

TEST(InputAngles, ShallowPinGivesTheJunctionWedge) {
  // Where the axis' plane meets the face, the pin's surface crosses the plate's face at the
  // construction angle: the plate keeps a 10-degree wedge under the pin there.
  for (double construction : {10.0, 25.0}) {
    const Composition c = pinEnteringPlate(construction);
    const auto angles = findSmallInputAngles(*c.oracle, c.features, 60, c.junctions.get());
    int junctions = 0;
    for (const SmallInputAngle& a : angles) {
      if (a.kind != "junction") continue;
      ++junctions;
      EXPECT_NEAR(a.angle_deg, construction, 1.0);
      EXPECT_EQ(a.input, "pin / plate");
      EXPECT_NEAR(a.location[2], 10, 1e-6) << "on the plate's top face";
      EXPECT_NEAR(a.location[1], 30, 1.0) << "near the axis' plane";
      std::cout << "[ figures  ] pin at " << construction << " degrees: junction wedge " << a.angle_deg << " at ("
                << a.location[0] << ", " << a.location[1] << ", " << a.location[2] << ")\n";
    }
    EXPECT_EQ(junctions, 1) << "one junction curve: the pin's entry into the top face";
    // Without the junction curves nothing of the kind is reported.
    for (const SmallInputAngle& a : findSmallInputAngles(*c.oracle, c.features, 60)) EXPECT_NE(a.kind, "junction");
  }
}

TEST(InputAngles, PerpendicularPinHasNoSmallJunctionWedge) {
  // Pin through the plate at a right angle: wedges of 90 (plate, outside) and 180 (pin).
  const TopoDS_Shape pin = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(30, 30, -10), gp_Dir(0, 0, 1)), 5, 30).Shape();
  const Composition c = compose({{pin, "pin"}, {BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 100, 60, 10).Shape(), "plate"}}, true);
  ASSERT_GT(c.junctions->size(), 0u);
  EXPECT_TRUE(findSmallInputAngles(*c.oracle, c.features, 60, c.junctions.get()).empty());
  // With the limit above 90 degrees the right-angle wedges show up, at 90 within rounding.
  const auto wide = findSmallInputAngles(*c.oracle, c.features, 91, c.junctions.get());
  int junctions = 0;
  for (const SmallInputAngle& a : wide)
    if (a.kind == "junction") {
      ++junctions;
      EXPECT_NEAR(a.angle_deg, 90, 1e-6);
    }
  EXPECT_EQ(junctions, 2) << "both circles";
}

TEST(InputAngles, PartRestingOnAChamferClosesAContactWedge) {
  const TopoDS_Shape block = test::chamferedBlock(40, 10);
  // Alone, the block's chamfer edges are obtuse (140 and 130 degrees): nothing small.
  const Composition alone = compose({{block, "block"}});
  for (const SmallInputAngle& a : findSmallInputAngles(*alone.oracle, alone.features, 60))
    EXPECT_NE(a.kind, "contact") << a.angle_deg;
  // A cover on the top face, reaching past the chamfer: a 40-degree gap along the chamfer's
  // upper edge (x = 16, y = 10), measured in 5-degree steps.
  const Composition covered = compose({{BRepPrimAPI_MakeBox(gp_Pnt(-5, 10, -5), gp_Pnt(25, 15, 15)).Shape(), "cover"},
                                       {block, "block"}});
  int contacts = 0;
  for (const SmallInputAngle& a : findSmallInputAngles(*covered.oracle, covered.features, 60)) {
    if (a.kind != "contact") continue;
    ++contacts;
    EXPECT_NEAR(a.angle_deg, 40, 5 + 1e-9);
    EXPECT_EQ(a.input, "block");
    EXPECT_NEAR(a.location[0], 16, 1e-6);
    EXPECT_NEAR(a.location[1], 10, 1e-6);
  }
  EXPECT_EQ(contacts, 1);
}


}  // namespace
}  // namespace oraclemesh
