// Triangle surfaces keep their sharp edges (features/TriangleSurfaceSharpEdges): an exported
// box meshed at the defaults is the box, to rounding, where without its edges the mesh cut
// them off (1.6 % of its volume in tet10) and the self-check refused it.
#include <gtest/gtest.h>

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeBox.hxx>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "discrete_shapes.h"
#include "domain/BrepSolid.h"
#include "job/Pipeline.h"
#include "mesh_checks.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

using nlohmann::json;

// Distance from p to the surface of the box [low, low + size].
double distanceToBoxSurface(const Point3& p, const Point3& low, const Point3& size) {
  double inside = std::numeric_limits<double>::infinity(), outside = 0;
  for (int k = 0; k < 3; ++k) {
    const double below = low[k] - p[k], above = p[k] - (low[k] + size[k]);
    inside = std::min(inside, std::max(-below, -above) < 0 ? 0 : std::min(-below, -above));
    outside = std::max(outside, std::max(below, above));
  }
  return outside > 0 ? outside : inside;
}

TEST(TriangleSurfaceEdges, AnStlBoxAtTheDefaultsIsTheBox) {
  const Point3 low{0, 0, 0}, size{40, 20, 10};
  json job = {{"inputs", {test::surfaceInput("box", test::triangleBox(low, size[0], size[1], size[2]), 1)}}, {"seed", 0}};
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  const double box = size[0] * size[1] * size[2];
  EXPECT_EQ(r.mesh.order(), 2);
  EXPECT_NEAR(test::volumePerMaterial(r.mesh).at(1), box, 1e-9 * box);
  EXPECT_TRUE(r.report.at("self_check").at("ok").get<bool>());
  EXPECT_EQ(r.report.at("features").at("sharp_edge_polylines").get<int>(), 12);
  // The box's twelve edges are chains of mesh edges: the feature edges add up to their length
  // and each lies on one of them.
  double featureLength = 0;
  for (const auto& e : r.mesh.feature_edges) {
    const Point3 &a = r.mesh.points[e[0]], &b = r.mesh.points[e[1]];
    featureLength += distance(a, b);
    int sharedFaces = 0;
    for (int k = 0; k < 3; ++k)
      sharedFaces += (a[k] == low[k] && b[k] == low[k]) || (a[k] == low[k] + size[k] && b[k] == low[k] + size[k]);
    EXPECT_EQ(sharedFaces, 2) << "feature edge off the box's edges";
  }
  EXPECT_NEAR(featureLength, 4 * (size[0] + size[1] + size[2]), 1e-9);
  EXPECT_EQ(test::featureEdgesNotTetEdges(r.mesh), 0);
  std::set<int64_t> onBoundary;
  for (const BoundaryTriangle& b : r.mesh.boundary) onBoundary.insert(b.v.begin(), b.v.end());
  for (int64_t v : onBoundary) EXPECT_LT(distanceToBoxSurface(r.mesh.points[v], low, size), 1e-9);

  // Without sharp edges the same mesh cuts the box's edges off: what the edges are for.
  job["features"] = {{"sharp_angle_deg", 0}};
  job["checks"] = "warn";
  const JobResult cut = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_LT(test::volumePerMaterial(cut.mesh).at(1), (1 - 1e-3) * box);
}

// Where a higher-priority input covers part of a triangle surface, the surface's edges in
// there are no edges of the composite boundary: they are clipped, as B-rep edges are. (The
// crease where the cover's face crosses the box's faces is no feature: junction curves are
// sections of two B-rep inputs only, so the mesh cuts that crease, 0.05 % of each volume.)
// A wedge as triangles: the triangle (0, 0), (L, 0), L (cos 20, sin 20) degrees extruded along
// z. Along its sharp edge at the origin the two side faces meet at 20 degrees: a small input
// angle of kind "dihedral" (before, only the B-rep faces' were measured, and the poor tets at
// such an edge were "not improved in the budget").
TEST(TriangleSurfaceEdges, ASmallDihedralAngleIsReported) {
  const double L = 30, H = 10, angle = 20 * M_PI / 180;
  test::Triangles wedge;
  const Point3 corners[3] = {{0, 0, 0}, {L, 0, 0}, {L * std::cos(angle), L * std::sin(angle), 0}};
  for (const Point3& c : corners) wedge.points.push_back(c);
  for (const Point3& c : corners) wedge.points.push_back({c[0], c[1], H});
  wedge.triangles = {{0, 2, 1}, {3, 4, 5}};  // bottom (normal -z), top
  for (int64_t i = 0; i < 3; ++i) {  // the sides, counter-clockwise seen from +z
    const int64_t j = (i + 1) % 3;
    wedge.triangles.push_back({i, j, j + 3});
    wedge.triangles.push_back({i, j + 3, i + 3});
  }
  json job = {{"inputs", {test::surfaceInput("wedge", wedge, 1)}}, {"element_order", 1}, {"checks", "warn"},
              {"seed", 0}, {"limits", {{"time_limit", 60}}}};
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl({}, 60));
  int dihedrals = 0;
  for (const json& a : r.report.at("small_input_angles")) {
    if (a.at("kind") != "dihedral") continue;
    ++dihedrals;
    EXPECT_EQ(a.at("input"), "wedge");
    EXPECT_NEAR(a.at("angle_deg").get<double>(), 20, 1e-9);
    const Point3 at = a.at("location").get<Point3>();
    EXPECT_NEAR(std::hypot(at[0], at[1]), 0, 1e-9);  // on the edge at the origin
  }
  EXPECT_EQ(dihedrals, 1);  // the 80 and 90 degree edges are not small
}

TEST(TriangleSurfaceEdges, EdgesInsideAHigherInputAreClipped) {
  const TopoDS_Shape cover = BRepPrimAPI_MakeBox(gp_Pnt(30, -5, -5), gp_Pnt(50, 25, 15)).Shape();
  const json job = {{"inputs",
                     {{{"name", "cover"}, {"brep", test::brepText(cover)}, {"material", 2}},
                      test::surfaceInput("box", test::triangleBox({0, 0, 0}, 40, 20, 10), 1)}},
                    {"seed", 0}};
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  const auto volumes = test::volumePerMaterial(r.mesh);
  EXPECT_NEAR(volumes.at(1), 30 * 20 * 10, 1e-3 * 6000);
  EXPECT_NEAR(volumes.at(2), 20 * 30 * 20, 1e-3 * 12000);
  EXPECT_TRUE(r.report.at("self_check").at("ok").get<bool>());
  EXPECT_EQ(test::featureEdgesNotTetEdges(r.mesh), 0);
  // No feature edge runs inside the cover (x > 30 within the box's y and z).
  for (const auto& e : r.mesh.feature_edges) {
    const Point3 middle = 0.5 * (r.mesh.points[e[0]] + r.mesh.points[e[1]]);
    const bool insideCover = middle[0] > 30 + 1e-9 && middle[0] < 50 && middle[1] > -5 + 1e-9 && middle[1] < 25 - 1e-9 &&
                             middle[2] > -5 + 1e-9 && middle[2] < 15 - 1e-9;
    EXPECT_FALSE(insideCover) << middle[0] << " " << middle[1] << " " << middle[2];
  }
}

// part.step as a CAD program exports it to STL (OpenCASCADE's tessellation, chord 0.1 mm, 30
// degrees): a slot's end is tessellated so that its line of sharp edges turns back on itself
// by 178 degrees at one vertex. Taken as one line, that 2-degree angle was no input angle:
// both engines refined there without end (the thesis engine over 60,000 vertices, Mesh_3's
// protection never done). The turn is a corner now, and the job ends at once.
TEST(TriangleSurfaceEdges, PartStepExportedAsStlMeshesAtTheDefaults) {
  const TopoDS_Shape part = BrepSolid::fromFile(test::cadDir() + "/part.step", "part")->shape();
  BRepMesh_IncrementalMesh(part, 0.1, Standard_False, 0.5236, Standard_False);
  const std::string stl = (std::filesystem::temp_directory_path() / "oraclemesh_part_step.stl").string();
  test::writeTessellationStl(part, stl);
  const json job = {{"inputs", {{{"name", "part"}, {"file", stl}, {"material", 1}}}}, {"seed", 0}};
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl({}, 60));  // a second or two; the hang ends here
  std::remove(stl.c_str());
  const json& part1 = r.report.at("self_check").at("materials").at("1");
  std::cout << "[figures] part.step as STL, defaults: " << r.mesh.tets.size() << " tets, "
            << r.report.at("features").at("polylines") << " polylines, volume "
            << 100 * part1.at("deviation").get<double>() << " %, min dihedral "
            << r.report.at("quality").at("min_dihedral_deg") << "\n";
  EXPECT_TRUE(r.report.at("self_check").at("ok").get<bool>());
  EXPECT_LT(std::abs(part1.at("deviation").get<double>()), 0.005);
  EXPECT_GE(r.report.at("features").at("sharp_edge_polylines").get<int>(), 20);
  EXPECT_EQ(test::featureEdgesNotTetEdges(r.mesh), 0);
}

}  // namespace
}  // namespace oraclemesh
