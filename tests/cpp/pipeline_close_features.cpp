// The cause of presse_asm.step not meshing with sharp edges at its default sizes, in small:
// parts in contact along a circle each sample it, so two copies of the circle a sagitta apart
// cross each other. Mesh_3's protecting balls of the two copies intersect wherever they cross,
// and it shrinks them a loop at a time without end (this job ran into its time limit in the
// feature protection before). The copies are now one curve, so the job finishes in seconds
// with every circle a single chain of mesh edges and the volumes right.
#include <BRepPrimAPI_MakeBox.hxx>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "close_curve_shapes.h"
#include "job/Pipeline.h"
#include "mesh_checks.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Total length of the mesh feature edges with both ends on the circle of radius r at height z.
double featureLengthOnCircle(const TetMesh& mesh, double z, double r, double tolerance) {
  auto on = [&](int64_t v) {
    const Point3& p = mesh.points[v];
    return std::abs(p[2] - z) < tolerance && std::abs(std::hypot(p[0], p[1]) - r) < tolerance;
  };
  double length = 0;
  for (const auto& [a, b] : mesh.feature_edges)
    if (on(a) && on(b)) length += distance(mesh.points[a], mesh.points[b]);
  return length;
}

TEST(CloseFeatures, PartsInContactAlongACircleMeshWithEveryCircleAsMeshEdges) {
  const auto shapes = test::plateWithPin();
  const nlohmann::json job = {
      {"inputs", {{{"name", "plate_pin"}, {"brep", test::brepText(test::compoundOf({shapes[0], shapes[1]}))},
                   {"materials", {1, 2}}}}},
      {"criteria", {{"default", {{"cell_size", 6}, {"facet_size", 6}, {"facet_distance", 0.05}, {"edge_size", 4}}}}},
      {"features", {{"sharp_angle_deg", 30}, {"junctions", true}}},
      {"engine", "cgal"},
      {"optimize", {{"perturb", false}}},
      {"limits", {{"time_limit", 120}}},
      {"seed", 0}};
  const auto start = std::chrono::steady_clock::now();
  const JobResult result = runJob(JobSpec::fromJson(job, ""), RunControl());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const TetMesh& mesh = result.mesh;
  EXPECT_TRUE(result.report.at("conformity").at("ok").get<bool>()) << result.report.at("conformity").dump();
  // Feature nodes are snapped onto their curves; a node the snap had to leave is still far
  // nearer its own circle than a second copy's chords would be.
  const double tolerance = 0.02;
  // One chain of edges per circle (chords: a little shorter than the arc; two copies would
  // give twice the length): the shared bottom circle, the hole's top edge (where the pin
  // leaves the plate) and the pin's top circle.
  const double circle = 2 * kPi * test::kPinRadius;
  for (double z : {0.0, test::kPlateThickness, test::kPinLength})
    EXPECT_NEAR(featureLengthOnCircle(mesh, z, test::kPinRadius, tolerance), circle, 0.01 * circle) << "z = " << z;
  EXPECT_LT(result.report.at("seconds").at("mesh3_protect_features").get<double>(), 10);

  // The parts do not overlap: each material's volume is its solid's.
  const std::map<int, double> volumes = test::volumePerMaterial(mesh);
  for (int k = 0; k < 2; ++k) {
    const double expected = test::volumeOf(shapes[k]);
    ASSERT_TRUE(volumes.count(k + 1)) << "material " << k + 1;
    EXPECT_NEAR(volumes.at(k + 1), expected, 0.01 * expected) << "material " << k + 1;
  }
  std::cout << "[ figures  ] " << mesh.tets.size() << " tets, " << mesh.feature_edges.size() << " feature edges, "
            << seconds << " s; seconds " << result.report.at("seconds").dump() << "\n";
}

// A box standing on another and overhanging its edge by 1: the upper box's bottom edges cross
// the lower box's top edge at (2, 10, 10) and (8, 10, 10), 1 and 2 from the curves' ends. Both
// curves are creases of the assembly on either side of the crossing, so each crossing must be
// a mesh vertex where four chains of feature edges meet. Cell sizes 3 and 5 once ended in an
// internal error (the crossing taken for a T, a zero-length feature edge at (8, 10, 10)); cell
// size 7 ended in one too, a second crossing 0.1 beside the first (the chord after a sample
// next to the crossing passing within reach of the other curve).
TEST(CloseFeatures, EdgesOfTouchingBoxesCrossingNearTheirEndsMeetAtAMeshVertex) {
  const TopoDS_Shape lower = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10, 10, 10).Shape();
  const TopoDS_Shape upper = BRepPrimAPI_MakeBox(gp_Pnt(2, 3, 10), 6, 8, 5).Shape();
  for (double size : {3.0, 5.0, 7.0}) {
    const nlohmann::json job = {{"inputs",
                                 {{{"name", "lower"}, {"brep", test::brepText(lower)}, {"material", 1}},
                                  {{"name", "upper"}, {"brep", test::brepText(upper)}, {"material", 2}}}},
                                {"criteria", {{"default", {{"cell_size", size}}}}},
                                {"seed", 0}};
    const JobResult result = runJob(JobSpec::fromJson(job, ""), RunControl());
    const TetMesh& mesh = result.mesh;
    EXPECT_EQ(test::featureEdgesNotTetEdges(mesh), 0) << "cell size " << size;
    for (const Point3& crossing : {Point3{2, 10, 10}, Point3{8, 10, 10}}) {
      int64_t vertex = -1;
      for (size_t v = 0; v < mesh.points.size(); ++v)
        if (distance(mesh.points[v], crossing) < 1e-9) vertex = static_cast<int64_t>(v);
      ASSERT_GE(vertex, 0) << "no mesh vertex at the crossing, cell size " << size;
      int chains = 0;
      for (const auto& [a, b] : mesh.feature_edges) chains += a == vertex || b == vertex;
      EXPECT_EQ(chains, 4) << "cell size " << size;
    }
    const std::map<int, double> volumes = test::volumePerMaterial(mesh);
    EXPECT_NEAR(volumes.at(1), 1000.0, 1e-9 * 1000) << "cell size " << size;
    EXPECT_NEAR(volumes.at(2), 240.0, 1e-9 * 240) << "cell size " << size;
  }
}

}  // namespace
}  // namespace oraclemesh
