// Sliver removal for any engine's mesh (optimizeTetMeshWithCgal): a Mesh_3 mesh of the demo
// assembly made without perturbation and exudation is rebuilt as a C3T3 and optimized. The
// optimizers must raise the worst dihedral angle while keeping the material volumes, the
// boundary on the CAD and every protected feature edge where it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <map>
#include <set>

#include "Error.h"
#include "cgal/Mesh3Engine.h"
#include "domain/BrepSolid.h"
#include "domain/Sphere.h"
#include "features/BrepSharpEdges.h"
#include "mesh/Quality.h"
#include "mesh/Topology.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"
#include "occt_reference.h"

namespace oraclemesh {
namespace {

struct DemoOracle {
  test::DemoAssembly shapes;
  std::shared_ptr<BrepSolid> pin = std::make_shared<BrepSolid>(shapes.pin, "Pin");
  std::shared_ptr<BrepSolid> cut = std::make_shared<BrepSolid>(shapes.cut, "CutCorner");
  std::shared_ptr<BrepSolid> plate = std::make_shared<BrepSolid>(shapes.plate, "Plate");
  HierarchicalOracle oracle{{{pin, Role::Material, 1}, {cut, Role::Cut, 0}, {plate, Role::Material, 2}}};
};

Mesh3Options demoOptions() {
  Mesh3Options options;
  options.criteria.defaults.cell_size = 5;
  options.criteria.defaults.facet_size = 4;
  options.criteria.defaults.facet_distance = 0.2;
  options.criteria.defaults.edge_size = 2;
  MaterialCriteria pin = options.criteria.defaults;
  pin.cell_size = 3;
  pin.facet_size = 2;
  pin.facet_distance = 0.05;
  options.criteria.per_material = {{1, pin}, {2, options.criteria.defaults}};
  return options;
}

FeatureGraph demoFeatures(const DemoOracle& demo) {
  FeatureGraph all;
  for (int entry : {0, 2}) {
    const auto& solid = dynamic_cast<const BrepSolid&>(*demo.oracle.entries()[entry].source);
    const FeatureGraph g = extractSharpEdges(solid, entry, 30, 2);
    all.polylines.insert(all.polylines.end(), g.polylines.begin(), g.polylines.end());
  }
  return clipToCompositeBoundary(all, demo.oracle);
}

// The Mesh_3 mesh before sliver removal (meshed once, shared by the tests).
const TetMesh& unoptimizedDemoMesh() {
  static const TetMesh mesh = [] {
    const DemoOracle demo;
    Mesh3Options options = demoOptions();
    options.perturb = options.exude = false;
    return meshWithCgalMesh3(demo.oracle, demoFeatures(demo), options, RunControl());
  }();
  return mesh;
}

using PointKey = std::array<double, 3>;
using EdgeKey = std::pair<PointKey, PointKey>;

std::set<EdgeKey> featureEdgesByPosition(const TetMesh& mesh) {
  std::set<EdgeKey> edges;
  for (const auto& [a, b] : mesh.feature_edges) {
    const PointKey pa = mesh.points[a], pb = mesh.points[b];
    edges.insert(std::minmax(pa, pb));
  }
  return edges;
}

std::set<std::array<PointKey, 4>> tetsByPosition(const TetMesh& mesh) {
  std::set<std::array<PointKey, 4>> tets;
  for (const auto& t : mesh.tets) {
    std::array<PointKey, 4> corners = {mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]};
    std::sort(corners.begin(), corners.end());
    tets.insert(corners);
  }
  return tets;
}

TEST(SliverRemoval, RebuildingWithoutOptimizersGivesTheSameMesh) {
  const DemoOracle demo;
  TetMesh mesh = unoptimizedDemoMesh();
  Mesh3Options options = demoOptions();
  options.perturb = options.exude = false;
  optimizeTetMeshWithCgal(mesh, demo.oracle, options, RunControl());
  const TetMesh& before = unoptimizedDemoMesh();
  EXPECT_EQ(tetsByPosition(mesh), tetsByPosition(before));
  EXPECT_EQ(featureEdgesByPosition(mesh), featureEdgesByPosition(before));
  EXPECT_EQ(measureQuality(mesh).tets_per_material, measureQuality(before).tets_per_material);
}

TEST(SliverRemoval, RaisesMinimumDihedralAndKeepsVolumesBoundaryAndFeatures) {
  const DemoOracle demo;
  const TetMesh& before = unoptimizedDemoMesh();
  ASSERT_FALSE(before.feature_edges.empty());
  TetMesh after = before;
  Mesh3Statistics stats;
  optimizeTetMeshWithCgal(after, demo.oracle, demoOptions(), RunControl(), &stats);

  const QualityReport q0 = measureQuality(before), q1 = measureQuality(after);
  std::cout << "[figures] sliver removal on the demo assembly: min dihedral " << q0.min_dihedral << " -> "
            << q1.min_dihedral << " deg, max " << q0.max_dihedral << " -> " << q1.max_dihedral << " deg, tets "
            << before.tets.size() << " -> " << after.tets.size() << ", perturb " << stats.seconds["perturb"]
            << " s, exude " << stats.seconds["exude"] << " s\n";
  EXPECT_GT(q1.min_dihedral, q0.min_dihedral + 1.0);
  EXPECT_EQ(q1.inverted, 0);

  const auto v0 = test::volumePerMaterial(before), v1 = test::volumePerMaterial(after);
  ASSERT_EQ(v1.size(), v0.size());
  for (const auto& [material, volume] : v0) EXPECT_NEAR(v1.at(material), volume, 1e-3 * volume) << material;

  // Feature vertices are not moved, so the protected edges are the same segments.
  EXPECT_EQ(featureEdgesByPosition(after), featureEdgesByPosition(before));

  // The boundary stays closed and conforming, and its vertices stay on the composite
  // boundary (perturbed surface vertices are put back onto it through the oracle).
  after.boundary = extractBoundary(after);
  const test::Conformity conformity = test::conformity(after);
  EXPECT_EQ(conformity.faces_shared_by_more_than_two, 0);
  EXPECT_EQ(conformity.open_boundary_edges, 0);
  EXPECT_EQ(conformity.inverted, 0);
  const double diagonal = demo.oracle.diagonal();
  double worst = 0;
  std::set<int64_t> boundaryVertices;
  for (const BoundaryTriangle& t : after.boundary) boundaryVertices.insert(t.v.begin(), t.v.end());
  for (int64_t v : boundaryVertices)
    worst = std::max(worst, demo.oracle.projectOnBoundary(after.points[v]).distance);
  EXPECT_LT(worst, 1e-5 * diagonal);

  // Deterministic: the same mesh in gives the same mesh out.
  TetMesh again = before;
  optimizeTetMeshWithCgal(again, demo.oracle, demoOptions(), RunControl());
  EXPECT_EQ(again.points, after.points);
  EXPECT_EQ(again.tets, after.tets);
  EXPECT_EQ(again.tet_materials, after.tet_materials);
}

TEST(SliverRemoval, RejectsATetMeshThatIsNotDelaunay) {
  // Two tets across the triangle c, d, e whose apexes a and b are close to it: b lies inside
  // the circumsphere of (a, c, d, e), so the Delaunay triangulation is the three tets around
  // the edge a-b instead.
  TetMesh mesh;
  mesh.points = {{0, 0, 0.3}, {0, 0, -0.3}, {1, 0, 0}, {-0.5, 0.866, 0}, {-0.5, -0.866, 0}};
  mesh.tets = {{0, 2, 4, 3}, {1, 2, 3, 4}};
  for (const auto& t : mesh.tets)
    ASSERT_GT(test::orientation(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]), 0);
  mesh.tet_materials = {1, 1};
  const HierarchicalOracle oracle({{std::make_shared<Sphere>(Point3{0, 0, 0}, 1.0, "ball"), Role::Material, 1}});
  try {
    optimizeTetMeshWithCgal(mesh, oracle, Mesh3Options(), RunControl());
    FAIL() << "a non-Delaunay mesh was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a cell of the Delaunay triangulation"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace oraclemesh
