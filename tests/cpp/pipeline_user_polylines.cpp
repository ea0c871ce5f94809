// User polylines (job features.polylines): kept as chains of mesh edges, on faces and inside
// the volume, split where they cross each other and the box's sharp edges.
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include <nlohmann/json.hpp>

#include "features/RuleSetQ.h"
#include "features/UserPolylines.h"
#include "job/Pipeline.h"
#include "mesh_checks.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

// Length of the segment a-b covered by mesh feature edges lying on it.
double coveredLength(const TetMesh& mesh, const Point3& a, const Point3& b, double tolerance) {
  double length = 0;
  for (const auto& e : mesh.feature_edges) {
    const Point3& p = mesh.points[e[0]];
    const Point3& q = mesh.points[e[1]];
    if (distanceToSegment(p, a, b) <= tolerance && distanceToSegment(q, a, b) <= tolerance) length += distance(p, q);
  }
  return length;
}

TEST(UserPolylines, ChainsOfMeshEdgesOnFacesAndInside) {
  const std::vector<std::vector<Point3>> lines = {
      {{0, 20, 20}, {40, 20, 20}},                 // across the top face, sharp edge to sharp edge
      {{20, 0, 20}, {20, 40, 20}},                 // crosses the first at (20, 20, 20)
      {{10, 10, 5}, {30, 30, 5}, {30, 10, 12}}};   // inside the block
  nlohmann::json polylines = nlohmann::json::array();
  for (const auto& line : lines) polylines.push_back(line);
  const nlohmann::json job = {
      {"inputs", {{{"name", "Block"}, {"brep", test::brepText(BRepPrimAPI_MakeBox(40, 40, 20).Shape())}, {"material", 1}}}},
      {"criteria", {{"default", {{"cell_size", 6}, {"facet_size", 6}, {"facet_distance", 1}, {"edge_size", 3}}}}},
      {"features", {{"polylines", polylines}}},
      {"element_order", 1},
      {"seed", 0}};
  const JobResult result = runJob(JobSpec::fromJson(job, ""), RunControl());
  const TetMesh& mesh = result.mesh;
  const double tolerance = 1e-9 * result.report.at("bbox_diagonal").get<double>();

  for (const auto& line : lines)
    for (size_t k = 0; k + 1 < line.size(); ++k)
      EXPECT_NEAR(coveredLength(mesh, line[k], line[k + 1], tolerance), distance(line[k], line[k + 1]), 1e-9)
          << "segment " << k << " of the polyline from (" << line[0][0] << ", " << line[0][1] << ", " << line[0][2] << ")";
  // The crossing and the T-junctions with the block's edges are mesh vertices.
  for (const Point3& meeting : std::vector<Point3>{{20, 20, 20}, {0, 20, 20}, {40, 20, 20}, {20, 0, 20}, {30, 30, 5}}) {
    double nearest = 1e9;
    for (const Point3& p : mesh.points) nearest = std::min(nearest, distance(p, meeting));
    EXPECT_LE(nearest, tolerance) << meeting[0] << ", " << meeting[1] << ", " << meeting[2];
  }
  EXPECT_NEAR(test::volumePerMaterial(mesh).at(1), 40 * 40 * 20, 1e-6 * 40 * 40 * 20);
  EXPECT_TRUE(result.report.at("conformity").at("ok").get<bool>());
}

TEST(UserPolylines, LeavingTheDomainIsAnErrorNamingThePolyline) {
  const nlohmann::json job = {
      {"inputs", {{{"name", "Block"}, {"brep", test::brepText(BRepPrimAPI_MakeBox(40, 40, 20).Shape())}, {"material", 1}}}},
      {"features", {{"polylines", {{{10, 10, 10}, {10, 10, 30}}}}}}};
  try {
    runJob(JobSpec::fromJson(job, ""), RunControl());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("features.polylines[0] leaves the meshed domain"), std::string::npos) << e.what();
  }
}

// A half circle on the block's top face given as chords plus its exact edge (what FreeCAD sends
// for a sketch arc), with sharp edges off: the only feature edges are the arc's, and their
// nodes lie on the circle, not on the chords.
TEST(UserPolylines, NodesOfAPolylineWithItsCadEdgeLieOnTheExactCurve) {
  const double radius = 12, pi = std::acos(-1.0);
  const Point3 centre{20, 20, 20};
  const TopoDS_Edge arc = BRepBuilderAPI_MakeEdge(
      GC_MakeArcOfCircle(gp_Pnt(32, 20, 20), gp_Pnt(20, 32, 20), gp_Pnt(8, 20, 20)).Value());
  nlohmann::json chords = nlohmann::json::array();
  const int segments = 8;  // chords up to 0.23 off the circle
  for (int k = 0; k <= segments; ++k) {
    const double a = pi * k / segments;
    chords.push_back({centre[0] + radius * std::cos(a), centre[1] + radius * std::sin(a), centre[2]});
  }
  const nlohmann::json job = {
      {"inputs", {{{"name", "Block"}, {"brep", test::brepText(BRepPrimAPI_MakeBox(40, 40, 20).Shape())}, {"material", 1}}}},
      {"criteria", {{"default", {{"cell_size", 6}, {"facet_size", 6}, {"facet_distance", 1}, {"edge_size", 2}}}}},
      {"features", {{"sharp_angle_deg", 0}, {"junctions", false},
                    {"polylines", {{{"points", chords}, {"brep", test::brepText(arc)}}}}}},
      {"element_order", 2},
      {"seed", 0}};
  const JobResult result = runJob(JobSpec::fromJson(job, ""), RunControl());
  const TetMesh& mesh = result.mesh;
  const double tolerance = 1e-9 * result.report.at("bbox_diagonal").get<double>();
  auto offCircle = [&](const Point3& p) {
    const double r = std::hypot(p[0] - centre[0], p[1] - centre[1]);
    return std::max({std::abs(r - radius), std::abs(p[2] - centre[2]), std::max(0.0, centre[1] - p[1])});
  };
  ASSERT_GT(mesh.feature_edges.size(), static_cast<size_t>(segments));
  double worst = 0, length = 0;
  for (const auto& e : mesh.feature_edges) {
    worst = std::max({worst, offCircle(mesh.points[e[0]]), offCircle(mesh.points[e[1]])});
    length += distance(mesh.points[e[0]], mesh.points[e[1]]);
  }
  EXPECT_LE(worst, tolerance);  // nodes on the chords would be up to 0.23 off
  EXPECT_LE(length, pi * radius);
  EXPECT_GE(length, 0.99 * pi * radius);
  // Second-order mid nodes of the arc's edges are on the circle too.
  std::set<std::pair<int64_t, int64_t>> arcEdges;
  for (const auto& e : mesh.feature_edges) arcEdges.insert(std::minmax(e[0], e[1]));
  ASSERT_EQ(mesh.tet_mid_nodes.size(), mesh.tets.size());
  static const int ends[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  double worstMid = 0;
  size_t midNodes = 0;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 6; ++k)
      if (arcEdges.count(std::minmax(mesh.tets[t][ends[k][0]], mesh.tets[t][ends[k][1]]))) {
        worstMid = std::max(worstMid, offCircle(mesh.points[mesh.tet_mid_nodes[t][k]]));
        ++midNodes;
      }
  EXPECT_GE(midNodes, mesh.feature_edges.size());
  EXPECT_LE(worstMid, tolerance);
}

// The edge of a hole on a plate's bottom face as an extra edge (FreeCAD sends chords plus the
// exact circle): the chords cut across the hole, outside the plate by their sagitta (0.61 mm
// here), yet the edge lies on the plate. Both engines keep it, with its nodes on the circle.
TEST(UserPolylines, AHoleEdgeOnAnOuterFaceIsKeptThoughItsChordsCrossTheHole) {
  const double radius = 8, pi = std::acos(-1.0);
  const Point3 centre{20, 20, 0};
  const TopoDS_Shape plate =
      BRepAlgoAPI_Cut(BRepPrimAPI_MakeBox(40, 40, 10).Shape(),
                      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20, 20, -1), gp::DZ()), radius, 12).Shape())
          .Shape();
  const TopoDS_Edge circle = BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(20, 20, 0), gp::DZ()), radius));
  nlohmann::json chords = nlohmann::json::array();
  const int segments = 8;
  for (int k = 0; k <= segments; ++k) {
    const double a = 2 * pi * (k % segments) / segments;
    chords.push_back({centre[0] + radius * std::cos(a), centre[1] + radius * std::sin(a), centre[2]});
  }
  for (const char* engine : {"cgal", "thesis"}) {
    const nlohmann::json job = {
        {"inputs", {{{"name", "Plate"}, {"brep", test::brepText(plate)}, {"material", 1}}}},
        {"criteria", {{"default", {{"cell_size", 5}, {"facet_size", 5}, {"facet_distance", 0.5}, {"edge_size", 2}}}}},
        {"features", {{"sharp_angle_deg", 0}, {"junctions", false},
                      {"polylines", {{{"points", chords}, {"brep", test::brepText(circle)}}}}}},
        {"engine", engine},
        {"seed", 0}};
    const JobResult result = runJob(JobSpec::fromJson(job, ""), RunControl());
    const TetMesh& mesh = result.mesh;
    const double tolerance = 1e-9 * result.report.at("bbox_diagonal").get<double>();
    double worst = 0, length = 0;
    for (const auto& e : mesh.feature_edges) {
      for (int64_t v : e) {
        const Point3& p = mesh.points[v];
        worst = std::max({worst, std::abs(std::hypot(p[0] - centre[0], p[1] - centre[1]) - radius), std::abs(p[2])});
      }
      length += distance(mesh.points[e[0]], mesh.points[e[1]]);
    }
    EXPECT_LE(worst, tolerance) << engine;
    EXPECT_LE(length, 2 * pi * radius) << engine;
    EXPECT_GE(length, 0.98 * 2 * pi * radius) << engine;
    EXPECT_TRUE(result.report.at("conformity").at("ok").get<bool>()) << engine;
  }
}

TEST(UserPolylines, ABrepThatIsNotOneEdgeIsRefusedNamingThePolyline) {
  const nlohmann::json job = {
      {"inputs", {{{"name", "Block"}, {"brep", test::brepText(BRepPrimAPI_MakeBox(40, 40, 20).Shape())}, {"material", 1}}}},
      {"features", {{"polylines", {{{"points", {{10, 10, 10}, {20, 10, 10}}},
                                    {"brep", test::brepText(BRepPrimAPI_MakeBox(1, 1, 1).Shape())}}}}}}};
  try {
    runJob(JobSpec::fromJson(job, ""), RunControl());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("features.polylines[0].brep holds 12 edges"), std::string::npos) << e.what();
  }
}

TEST(UserPolylines, MalformedPolylinesAreRefusedByTheJob) {
  for (const nlohmann::json& bad : {nlohmann::json{{{0, 0, 0}}}, nlohmann::json{{{0, 0, 0}, {0, 0, 0}}},
                                    nlohmann::json{{{0, 0}, {1, 1}}}, nlohmann::json{"line"}}) {
    const nlohmann::json job = {{"inputs", {{{"name", "Ball"}, {"sphere", {{"center", {0, 0, 0}}, {"radius", 1}}}}}},
                                {"features", {{"polylines", bad}}}};
    EXPECT_THROW(JobSpec::fromJson(job, ""), InputError) << bad.dump();
  }
}

TEST(UserPolylines, SharpAngleZeroMeansNoSharpEdgesOtherAnglesMustBeBelow180) {
  auto withAngle = [](const nlohmann::json& angle) {
    return nlohmann::json{{"inputs", {{{"name", "Ball"}, {"sphere", {{"center", {0, 0, 0}}, {"radius", 1}}}}}},
                          {"features", {{"sharp_angle_deg", angle}}}};
  };
  EXPECT_EQ(JobSpec::fromJson(withAngle(0), "").sharp_angle_deg, 0.0);
  for (const nlohmann::json& bad : {nlohmann::json(-1), nlohmann::json(180), nlohmann::json("30")})
    EXPECT_THROW(JobSpec::fromJson(withAngle(bad), ""), InputError) << bad.dump();
}

TEST(SplitAtCrossings, CrossingBecomesASharedEndPoint) {
  FeatureGraph graph;
  FeaturePolyline edge;
  edge.points = {{0, 0, 0}, {10, 0, 0}};
  edge.source = 0;
  edge.edge = 3;
  FeaturePolyline user;
  user.points = {{5, -5, 0}, {5, 5, 0}};
  user.user = 0;
  graph.polylines = {edge, user};
  const FeatureGraph split = splitAtCrossings(graph, 1e-9);
  ASSERT_EQ(split.polylines.size(), 4u);
  int meetingEnds = 0;
  for (const FeaturePolyline& pl : split.polylines) {
    ASSERT_EQ(pl.points.size(), 2u);
    for (const Point3& p : {pl.points.front(), pl.points.back()}) meetingEnds += p == Point3{5, 0, 0};
  }
  EXPECT_EQ(meetingEnds, 4);
  EXPECT_EQ(split.polylines[0].edge, 3);  // pieces keep their origin
  EXPECT_EQ(split.polylines[3].user, 0);
}

}  // namespace
}  // namespace oraclemesh
