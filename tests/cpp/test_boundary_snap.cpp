// The flat-sliver removal before the boundary snap (src/core/mesh/BoundarySnap) on two
// hand-made tets: a corner tet and a tet on its slanted face that goes flat once its apex is
// on that face's plane.
#include <gtest/gtest.h>

#include "mesh/BoundarySnap.h"
#include "mesh/Topology.h"
#include "mesh_checks.h"
#include "mesh_fixtures.h"

namespace oraclemesh {
namespace {

// The corner tet {0, 1, 2, 3} and tet {1, 2, 3, 4} beyond its face x + y + z = 1, whose apex
// 4 is about to go onto that plane (`target`): a flat tet with three faces outside.
struct FlatSliverOnSurface {
  TetMesh mesh = test::cornerTet();
  std::vector<Point3> target;
  FlatSliverOnSurface() {
    mesh.points.push_back({0.4, 0.4, 0.4});
    std::array<int64_t, 4> sliver{1, 2, 3, 4};
    if (test::orientation(mesh.points[1], mesh.points[2], mesh.points[3], mesh.points[4]) < 0) std::swap(sliver[0], sliver[1]);
    mesh.tets.push_back(sliver);
    mesh.tet_materials.push_back(1);
    mesh.boundary = extractBoundary(mesh);
    target = mesh.points;
    target[4] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  }
};

TEST(FlatSurfaceSlivers, AFlatTetWithThreeOuterFacesIsRemoved) {
  FlatSliverOnSurface s;
  int64_t kept = 0;
  EXPECT_EQ(removeFlatSurfaceSlivers(s.mesh, s.target, kept), 1);
  EXPECT_EQ(kept, 0);
  ASSERT_EQ(s.mesh.tets.size(), 1u);
  EXPECT_EQ(s.mesh.boundary.size(), 4u);
}

// A feature edge whose only tet is the sliver would leave the mesh with it.
TEST(FlatSurfaceSlivers, TheLastTetOnAFeatureEdgeStays) {
  FlatSliverOnSurface s;
  s.mesh.feature_edges = {{1, 4}};
  s.mesh.feature_edge_curves = {0};
  int64_t kept = 0;
  EXPECT_EQ(removeFlatSurfaceSlivers(s.mesh, s.target, kept), 0);
  EXPECT_EQ(kept, 1);
  EXPECT_EQ(s.mesh.tets.size(), 2u);
  EXPECT_EQ(test::featureEdgesNotTetEdges(s.mesh), 0);
}

// Edge {1, 2} is also an edge of the corner tet: the sliver goes, the edge stays.
TEST(FlatSurfaceSlivers, ASliverOnAFeatureEdgeOtherTetsHaveIsRemoved) {
  FlatSliverOnSurface s;
  s.mesh.feature_edges = {{1, 2}};
  s.mesh.feature_edge_curves = {0};
  int64_t kept = 0;
  EXPECT_EQ(removeFlatSurfaceSlivers(s.mesh, s.target, kept), 1);
  EXPECT_EQ(kept, 0);
  EXPECT_EQ(s.mesh.tets.size(), 1u);
  EXPECT_EQ(test::featureEdgesNotTetEdges(s.mesh), 0);
}

}  // namespace
}  // namespace oraclemesh
