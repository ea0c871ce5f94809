// Sharp B-rep edges as feature polylines, and their clipping to the composite boundary.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Ax2.hxx>

#include <cstdlib>
#include <iostream>
#include <map>
#include <set>

#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"
#include "features/BrepSharpEdges.h"
#include "features/CurveSampling.h"

#include "occt_checks.h"
#include "small_angle_shapes.h"

namespace oraclemesh {
namespace {

constexpr int kPartStepSharpEdges = 50;  // of 70 edges, 2 of them seams

using test::cadDir;
using test::distanceToShape;


bool isSeamOf(const BrepSolid& solid, int edge) {
  for (int f : solid.facesOfEdge(edge))
    if (BRep_Tool::IsClosed(solid.edge(edge), solid.face(f))) return true;
  return false;
}

// Structural checks every extracted graph must pass.
void expectWellFormed(const BrepSolid& solid, const FeatureGraph& graph, int source, double maxSegment) {
  const double diagonal = solid.bbox().diagonal();
  std::set<int> curves;
  for (const FeaturePolyline& pl : graph.polylines) {
    ASSERT_GE(pl.points.size(), 2u);
    EXPECT_TRUE(curves.insert(pl.curve).second) << "duplicate curve id " << pl.curve;
    EXPECT_EQ(pl.source, source);
    ASSERT_GE(pl.edge, 0);
    ASSERT_LT(pl.edge, solid.edgeCount());
    EXPECT_FALSE(isSeamOf(solid, pl.edge)) << "seam edge " << pl.edge << " taken as a feature";
    EXPECT_FALSE(BRep_Tool::Degenerated(solid.edge(pl.edge)));
    for (size_t i = 0; i + 1 < pl.points.size(); ++i)
      EXPECT_LE(distance(pl.points[i], pl.points[i + 1]), maxSegment * (1 + 1e-9));
    for (const Point3& p : pl.points)
      EXPECT_LT(solid.projectOnEdge(p, pl.edge).distance, 1e-9 * diagonal) << "polyline point off its B-rep edge";
  }
  // Ends are the exact B-rep vertices.
  TopTools_IndexedMapOfShape vertices;
  TopExp::MapShapes(solid.shape(), TopAbs_VERTEX, vertices);
  std::set<Point3> vertexPoints;
  for (int i = 1; i <= vertices.Extent(); ++i) {
    const gp_Pnt p = BRep_Tool::Pnt(TopoDS::Vertex(vertices(i)));
    vertexPoints.insert({p.X(), p.Y(), p.Z()});
  }
  for (const FeaturePolyline& pl : graph.polylines) {
    EXPECT_TRUE(vertexPoints.count(pl.points.front()));
    EXPECT_TRUE(vertexPoints.count(pl.points.back()));
  }
}

TEST(SharpEdges, BoxHasTwelveWithSharedCorners) {
  BrepSolid solid(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "box");
  const FeatureGraph graph = extractSharpEdges(solid, 0, 30, 4);
  ASSERT_EQ(graph.polylines.size(), 12u);
  expectWellFormed(solid, graph, 0, 4);
  // Each corner ends exactly three polylines, with bitwise-equal coordinates.
  std::map<Point3, int> ends;
  for (const FeaturePolyline& pl : graph.polylines) {
    ++ends[pl.points.front()];
    ++ends[pl.points.back()];
  }
  EXPECT_EQ(ends.size(), 8u);
  for (const auto& [p, n] : ends) EXPECT_EQ(n, 3);
  // 30 mm edge at 4 mm segments: 8 segments.
  size_t longest = 0;
  for (const FeaturePolyline& pl : graph.polylines) longest = std::max(longest, pl.points.size());
  EXPECT_EQ(longest, 9u);
}

TEST(SharpEdges, CylinderHasTwoCirclesAndNoSeam) {
  BrepSolid solid(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 5, 20).Shape(), "pin");
  const FeatureGraph graph = extractSharpEdges(solid, 3, 30, 2);
  ASSERT_EQ(graph.polylines.size(), 2u);
  expectWellFormed(solid, graph, 3, 2);
  for (const FeaturePolyline& pl : graph.polylines) {
    EXPECT_EQ(pl.points.front(), pl.points.back()) << "a full circle is a closed polyline";
    EXPECT_GE(pl.points.size(), 17u);  // 31.4 mm at <= 2 mm
    EXPECT_EQ(pl.curve, 3 * kCurvesPerSource + pl.edge);
    for (const Point3& p : pl.points) EXPECT_NEAR(std::hypot(p[0], p[1]), 5, 1e-12);
  }
}

TEST(SharpEdges, TangentFilletEdgesAreNotSharp) {
  // One filleted edge: the fillet meets its two planes tangentially (2 edges left out); its
  // two arcs meet the end faces at 90 degrees. 11 box edges + 2 arcs remain sharp.
  TopoDS_Shape boxShape = BRepPrimAPI_MakeBox(10, 10, 10).Shape();
  BRepFilletAPI_MakeFillet rounding(boxShape);
  rounding.Add(2, TopoDS::Edge(TopExp_Explorer(boxShape, TopAbs_EDGE).Current()));
  rounding.Build();
  ASSERT_TRUE(rounding.IsDone());
  BrepSolid solid(rounding.Shape(), "rounded box");
  ASSERT_EQ(solid.edgeCount(), 15);
  const FeatureGraph graph = extractSharpEdges(solid, 0, 30, 3);
  EXPECT_EQ(graph.polylines.size(), 13u);
  expectWellFormed(solid, graph, 0, 3);
  // Below the threshold nothing changes for 90-degree edges; at 95 degrees none is sharp.
  EXPECT_EQ(extractSharpEdges(solid, 0, 89, 3).polylines.size(), 13u);
  EXPECT_EQ(extractSharpEdges(solid, 0, 95, 3).polylines.size(), 0u);
}

TEST(SharpEdges, SegmentsFollowTheLocalLengthAlongAnEdge) {
  // A 100 mm box edge along x whose local length grows from 0.1 mm at x = 0 by 0.3 per mm (a
  // short edge's size graded as the sizing field grades it): the segments grow with it instead
  // of all taking the smallest length (1000 of them).
  BrepSolid solid(BRepPrimAPI_MakeBox(100, 20, 30).Shape(), "bar");
  auto local = [](const Point3& p) { return 0.1 + 0.3 * std::abs(p[0]); };
  const FeatureGraph graph = extractSharpEdges(solid, 0, 30, 50, 0, local);
  expectWellFormed(solid, graph, 0, 50);
  const FeaturePolyline* alongX = nullptr;
  for (const FeaturePolyline& pl : graph.polylines)
    if (std::abs(pl.points.front()[1]) + std::abs(pl.points.front()[2]) == 0 &&
        std::abs(pl.points.back()[1]) + std::abs(pl.points.back()[2]) == 0)
      alongX = &pl;
  ASSERT_NE(alongX, nullptr);
  // The integral of 1 / (0.1 + 0.3 x) over [0, 100] is ln(301) / 0.3 = 19.0 segments.
  const size_t segments = alongX->points.size() - 1;
  EXPECT_GE(segments, 19u);
  EXPECT_LE(segments, 21u);
  double total = 0;
  for (size_t i = 0; i < segments; ++i) {
    const Point3 &a = alongX->points[i], &b = alongX->points[i + 1];
    const double length = distance(a, b);
    total += length;
    EXPECT_LE(length, local(0.5 * (a + b)) * 1.02) << "segment " << i << " longer than its local length";
    if (i > 0) {  // neighbours differ as the local length does (0.3 per mm), not by jumps
      const double before = distance(alongX->points[i - 1], a);
      EXPECT_LE(length / before, 1.5) << "segment " << i;
    }
  }
  EXPECT_NEAR(total, 100, 1e-9);
  EXPECT_LT(distance(alongX->points[0], alongX->points[1]), 0.2);  // the short end stays fine
}

TEST(SharpEdges, PartStep) {
  const auto solid = BrepSolid::fromFile(cadDir() + "/part.step", "part");
  const double segment = solid->bbox().diagonal() / 40;
  const FeatureGraph graph = extractSharpEdges(*solid, 0, 30, segment);
  expectWellFormed(*solid, graph, 0, segment);
  int seams = 0;
  for (int e = 0; e < solid->edgeCount(); ++e) seams += isSeamOf(*solid, e);
  std::cout << "[ counts   ] part.step: " << solid->edgeCount() << " edges, " << seams << " seams, "
            << graph.polylines.size() << " sharp at 30 degrees\n";
  EXPECT_EQ(static_cast<int>(graph.polylines.size()), kPartStepSharpEdges);
  EXPECT_LE(static_cast<int>(graph.polylines.size()), solid->edgeCount() - seams);
}

TEST(SharpEdges, NarrowCornersAreSampledCloseToTheCurves) {
  // A line and an arc leaving a vertex tangentially (a cusp): each arc chord must stay within
  // a quarter of the gap to the line (or 1e-4 of the diagonal), or moving mesh nodes from the
  // chords onto the arc would fold elements between the two curves. Sampled only by length and
  // sagitta, the chords next to the corner do not: there the gap shrinks with the square of
  // the distance, like the sagitta.
  const BrepSolid solid(test::cusp(10, 3, 2), "cusp");
  const double diagonal = solid.bbox().diagonal(), segment = 2;
  const FeatureGraph graph = extractSharpEdges(solid, 0, 30, segment);
  expectWellFormed(solid, graph, 0, segment);
  int arc = -1, line = -1;
  for (const FeaturePolyline& pl : graph.polylines) {
    const Point3 first = pl.points[1] - pl.points[0];
    if (std::abs(pl.points[0][2]) > 1e-9 || std::abs(first[2]) > 1e-9) continue;  // bottom face only
    (std::abs(first[1]) > 1e-9 ? arc : line) = pl.edge;
  }
  ASSERT_GE(arc, 0);
  ASSERT_GE(line, 0);
  // Worst chord sagitta relative to what the corner allows, over a polyline of the arc.
  auto worstRatio = [&](const std::vector<Point3>& points) {
    double worst = 0;
    for (size_t i = 0; i + 1 < points.size(); ++i) {
      const BoundaryProjection onArc = solid.projectOnEdge(0.5 * (points[i] + points[i + 1]), arc);
      const double gap = solid.projectOnEdge(onArc.point, line).distance;
      worst = std::max(worst, onArc.distance / std::max(0.25 * gap, 1e-4 * diagonal));
    }
    return worst;
  };
  for (const FeaturePolyline& pl : graph.polylines)
    if (pl.edge == arc) EXPECT_LE(worstRatio(pl.points), 1.0 + 1e-6);
  const BRepAdaptor_Curve curve(solid.edge(arc));
  std::vector<Point3> uniform;
  for (double u : polylineParameters(curve, curve.FirstParameter(), curve.LastParameter(), segment,
                                     featureSagittaTolerance(segment, diagonal), 1))
    uniform.push_back({curve.Value(u).X(), curve.Value(u).Y(), curve.Value(u).Z()});
  EXPECT_GT(worstRatio(uniform), 2.0) << "the length and sagitta bounds alone would do here";
}

// ---- clipping ------------------------------------------------------------------------------

// A plate (box 40 x 40 x 10, entry 1) under a higher-priority pin (cylinder r = 5 along z
// through (40, 20), entry 0) that pierces the plate's face x = 40 and two of its edges.
struct PinThroughPlate {
  std::shared_ptr<BrepSolid> pin = std::make_shared<BrepSolid>(
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(40, 20, -5), gp_Dir(0, 0, 1)), 5, 20).Shape(), "pin");
  std::shared_ptr<BrepSolid> plate = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(40, 40, 10).Shape(), "plate");
};

FeatureGraph allSharpEdges(const HierarchicalOracle& oracle, double segment) {
  FeatureGraph all;
  for (size_t i = 0; i < oracle.entries().size(); ++i) {
    const auto* solid = dynamic_cast<const BrepSolid*>(oracle.entries()[i].source.get());
    FeatureGraph g = extractSharpEdges(*solid, static_cast<int>(i), 30, segment);
    all.polylines.insert(all.polylines.end(), g.polylines.begin(), g.polylines.end());
  }
  return all;
}

TEST(ClipToCompositeBoundary, PlateEdgesInsideThePinAreRemoved) {
  PinThroughPlate model;
  HierarchicalOracle oracle({{model.pin, Role::Material, 1}, {model.plate, Role::Material, 2}});
  const double diagonal = oracle.diagonal();
  const FeatureGraph all = allSharpEdges(oracle, 3);
  ASSERT_EQ(all.polylines.size(), 14u);  // 2 pin circles + 12 plate edges
  const FeatureGraph clipped = clipToCompositeBoundary(all, oracle);
  // The two plate edges along x = 40 are split around the pin; the pin is untouched.
  EXPECT_EQ(clipped.polylines.size(), 16u);
  std::set<int> ids;
  int cutEnds = 0;
  for (const FeaturePolyline& pl : clipped.polylines) {
    EXPECT_TRUE(ids.insert(pl.curve).second);
    const BrepSolid& solid = pl.source == 0 ? *model.pin : *model.plate;
    for (const Point3& p : pl.points) EXPECT_LT(solid.projectOnEdge(p, pl.edge).distance, 1e-9 * diagonal);
    for (const Point3& p : {pl.points.front(), pl.points.back()}) {
      if (pl.source != 1 || std::abs(p[0] - 40) > 1e-9 || std::abs(p[1] - 20) > 5.5) continue;
      if (p[1] == 0 || p[1] == 40) continue;  // plate corners
      ++cutEnds;
      // The cut end lies on the pin surface and on the plate edge.
      EXPECT_NEAR(std::hypot(p[0] - 40, p[1] - 20), 5, 1e-9 * diagonal);
      EXPECT_NEAR(std::abs(p[1] - 20), 5, 1e-9 * diagonal);
    }
    // Nothing kept strictly inside the pin.
    if (pl.source == 1)
      for (const Point3& p : pl.points) EXPECT_GE(std::hypot(p[0] - 40, p[1] - 20), 5 - 1e-9 * diagonal);
  }
  EXPECT_EQ(cutEnds, 4);
}

TEST(ClipToCompositeBoundary, ObliqueCrossingEndsOnBothSurfaces) {
  // A tilted pin crosses the plate's top edges obliquely; cut ends must be on the pin surface
  // and on the plate edge within 1e-9 of the diagonal.
  auto pin = std::make_shared<BrepSolid>(
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20, 20, -10), gp_Dir(0.3, 0.2, 1)), 4, 40).Shape(), "tilted pin");
  auto plate = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 30, 40, 10).Shape(), "plate");
  HierarchicalOracle oracle({{pin, Role::Material, 1}, {plate, Role::Material, 2}});
  const double diagonal = oracle.diagonal();
  const FeatureGraph clipped = clipToCompositeBoundary(allSharpEdges(oracle, 2.5), oracle);
  int cutEnds = 0;
  for (const FeaturePolyline& pl : clipped.polylines) {
    if (pl.source != 1) continue;
    for (const Point3& p : {pl.points.front(), pl.points.back()}) {
      const double toPin = distanceToShape(p, pin->shape());
      if (toPin > 1e-6 * diagonal) continue;
      ++cutEnds;
      EXPECT_LT(toPin, 1e-9 * diagonal);
      EXPECT_LT(plate->projectOnEdge(p, pl.edge).distance, 1e-9 * diagonal);
    }
  }
  EXPECT_GT(cutEnds, 0);
}

TEST(ClipToCompositeBoundary, CutEdgesOnlyWhereMaterialIsBehindThem) {
  // A cut box takes the corner x, y > 30 out of the plate; the cut's vertical edge at
  // (30, 30) is a feature only through the plate's thickness.
  auto cut = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(30, 30, -5), 20, 20, 20).Shape(), "cut");
  auto plate = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(40, 40, 10).Shape(), "plate");
  HierarchicalOracle oracle({{cut, Role::Cut, 0}, {plate, Role::Material, 2}});
  const double diagonal = oracle.diagonal();
  const FeatureGraph clipped = clipToCompositeBoundary(allSharpEdges(oracle, 3), oracle);
  int cutPieces = 0;
  for (const FeaturePolyline& pl : clipped.polylines) {
    if (pl.source == 0) {
      ++cutPieces;
      ASSERT_EQ(pl.points.size() >= 2, true);
      const Point3 low = pl.points.front()[2] < pl.points.back()[2] ? pl.points.front() : pl.points.back();
      const Point3 high = pl.points.front()[2] < pl.points.back()[2] ? pl.points.back() : pl.points.front();
      EXPECT_NEAR(low[0], 30, 1e-12);
      EXPECT_NEAR(low[1], 30, 1e-12);
      EXPECT_NEAR(low[2], 0, 1e-9 * diagonal);
      EXPECT_NEAR(high[2], 10, 1e-9 * diagonal);
    } else {
      for (const Point3& p : pl.points) EXPECT_FALSE(p[0] > 30 + 1e-6 && p[1] > 30 + 1e-6) << "plate edge kept in the cut";
    }
  }
  EXPECT_EQ(cutPieces, 1);
  // Plate: 7 edges untouched, the 4 edges running into the cut corner shortened, the
  // vertical edge at (40, 40) removed: 11 pieces.
  EXPECT_EQ(clipped.polylines.size() - cutPieces, 11u);
}

}  // namespace
}  // namespace oraclemesh
