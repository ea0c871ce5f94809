// The improvement stage (src/core/improve) on real CAD: part.step with sharp edges at the
// default sizes, meshed once with the stage off; the stage then runs on that mesh. It must
// lower the number of poor tets without lowering the minimum, keep every feature edge a tet
// edge, every boundary triangle a face of its tet, every boundary node on the CAD, each
// material's volume to 1e-9, and give the same mesh twice.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "RunControl.h"
#include "improve/MeshImprovement.h"
#include "job/Pipeline.h"
#include "mesh/Quality.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"
#include "occt_checks.h"
#include "domain/BrepSolid.h"

namespace oraclemesh {
namespace {

const JobResult& partWithoutStage() {
  static const JobResult r = runJob(
      JobSpec::fromJson({{"inputs", {{{"name", "part"}, {"file", test::cadDir() + "/part.step"}, {"material", 1}}}},
                         {"features", {{"sharp_angle_deg", 30}, {"junctions", true}}},
                         {"engine", "thesis"},
                         {"element_order", 1},
                         {"optimize", {{"improve", false}}},
                         {"seed", 0}},
                        ""),
      RunControl());
  return r;
}

TEST(ImprovementStage, PartStepFewerPoorTetsWithBoundaryFeaturesAndVolumesKept) {
  const TetMesh& before = partWithoutStage().mesh;
  ASSERT_EQ(partWithoutStage().report.at("improve").at("enabled"), false);
  TetMesh after = before;
  const ImprovementStats s = improveMesh(after, ImprovementOptions{}, RunControl());
  std::cout << "[ figures  ] part.step stage: min dihedral " << s.min_dihedral_before << " -> " << s.min_dihedral_after
            << ", under 5/10/15 deg " << s.before.under5 << "/" << s.before.under10 << "/" << s.before.under15 << " -> "
            << s.after.under5 << "/" << s.after.under10 << "/" << s.after.under15 << ", 3-2 " << s.flips32 << ", 4-4 "
            << s.flips44 << ", 5..7 " << s.edge_removals << ", 2-3 " << s.flips23 << ", smoothed "
            << s.smoothed_interior << "/" << s.smoothed_surface << "/" << s.smoothed_feature << ", " << s.seconds
            << " s\n";
  EXPECT_GE(s.min_dihedral_after, s.min_dihedral_before);
  EXPECT_LT(s.after.under5, s.before.under5);
  EXPECT_LT(s.after.under10, s.before.under10);
  EXPECT_LT(s.after.under15, s.before.under15);
  EXPECT_GT(s.flips32 + s.flips44 + s.edge_removals, 0);
  EXPECT_GT(s.smoothed_interior, 0);
  EXPECT_GT(s.smoothed_surface, 0);
  // No feature edge got longer than the longest was (the edge size holds): Rule Set Q's
  // equalised subsegments leave feature vertices here no room along their lines.
  double longestBefore = 0, longestAfter = 0;
  for (const auto& e : before.feature_edges)
    longestBefore = std::max(longestBefore, distance(before.points[e[0]], before.points[e[1]]));
  for (const auto& e : after.feature_edges)
    longestAfter = std::max(longestAfter, distance(after.points[e[0]], after.points[e[1]]));
  EXPECT_LE(longestAfter, longestBefore);

  EXPECT_EQ(test::featureEdgesNotTetEdges(after), 0);
  EXPECT_EQ(after.feature_edges, before.feature_edges);
  EXPECT_EQ(test::boundaryFaces(after), test::boundaryFaces(before));
  for (const auto& t : after.tets)
    EXPECT_GT(test::orientation(after.points[t[0]], after.points[t[1]], after.points[t[2]], after.points[t[3]]), 0);
  const auto vb = test::volumePerMaterial(before), va = test::volumePerMaterial(after);
  for (const auto& [material, volume] : vb) EXPECT_NEAR(va.at(material), volume, 1e-9 * volume);

  // Boundary nodes the stage moved are still on the CAD, as close as the snap put them.
  const auto solid = BrepSolid::fromFile(test::cadDir() + "/part.step", "part");
  const double diagonal = solid->bbox().diagonal();
  int64_t moved = 0;
  for (int64_t v : test::boundaryNodes(after)) {
    if (after.points[v] == before.points[v]) continue;
    ++moved;
    EXPECT_LT(test::distanceToShape(after.points[v], solid->shape()), 1e-9 * diagonal) << v;
  }
  EXPECT_GT(moved, 0);
}

TEST(ImprovementStage, SameMeshTwice) {
  TetMesh a = partWithoutStage().mesh, b = partWithoutStage().mesh;
  improveMesh(a, ImprovementOptions{}, RunControl());
  improveMesh(b, ImprovementOptions{}, RunControl());
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.tet_materials, b.tet_materials);
  EXPECT_EQ(a.points, b.points);
}

}  // namespace
}  // namespace oraclemesh
