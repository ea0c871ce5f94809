// BrepTopology, the B-rep faces and edges the feature, planar-face and job layers read through
// Source::brepTopology(): a B-rep solid answers with itself, as BrepSolid's own accessors
// do; every other kind of source answers nullptr.
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <TopAbs_ShapeEnum.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <gp_Pnt.hxx>

#include <array>
#include <cmath>
#include <memory>
#include <set>
#include <vector>

#include "domain/BrepSolid.h"
#include "domain/BrepTopology.h"
#include "domain/HierarchicalOracle.h"
#include "domain/Sphere.h"
#include "domain/TriangleSurface.h"

namespace oraclemesh {
namespace {

// The box [1, 11] x [2, 22] x [3, 33].
std::shared_ptr<BrepSolid> box() {
  return std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(1, 2, 3), gp_Pnt(11, 22, 33)).Shape(), "box");
}

TEST(BrepTopology, BoxHasSixFacesTwelveEdgesAndTwoFacesPerEdge) {
  const std::shared_ptr<BrepSolid> solid = box();
  const SourcePtr source = solid;
  const BrepTopology* topology = source->brepTopology();
  ASSERT_NE(topology, nullptr);
  EXPECT_EQ(topology, static_cast<const BrepTopology*>(solid.get()));
  EXPECT_EQ(topology->name(), "box");
  EXPECT_EQ(topology->faceCount(), 6);
  EXPECT_EQ(topology->edgeCount(), 12);
  std::vector<int> edgesOfFace(6, 0);
  for (int e = 0; e < topology->edgeCount(); ++e) {
    const std::vector<int>& faces = topology->facesOfEdge(e);
    ASSERT_EQ(faces.size(), 2u) << "edge " << e;
    EXPECT_NE(faces[0], faces[1]) << "edge " << e;
    for (int f : faces) {
      ASSERT_GE(f, 0);
      ASSERT_LT(f, 6);
      ++edgesOfFace[f];
    }
  }
  for (int f = 0; f < 6; ++f) EXPECT_EQ(edgesOfFace[f], 4) << "face " << f;
}

TEST(BrepTopology, AnswersAsTheSolidItself) {
  const std::shared_ptr<BrepSolid> solid = box();
  const BrepTopology& topology = *static_cast<const Source&>(*solid).brepTopology();
  EXPECT_TRUE(topology.shape().IsSame(solid->shape()));
  const Bbox a = topology.bbox(), b = solid->bbox();
  EXPECT_EQ(a.min, b.min);
  EXPECT_EQ(a.max, b.max);
  EXPECT_NEAR(a.min[0], 1, 1e-6);
  EXPECT_NEAR(a.max[2], 33, 1e-6);
  // Faces and edges in TopExp::MapShapes order on the shape, the same objects as BrepSolid's.
  TopTools_IndexedMapOfShape faceMap, edgeMap;
  TopExp::MapShapes(topology.shape(), TopAbs_FACE, faceMap);
  TopExp::MapShapes(topology.shape(), TopAbs_EDGE, edgeMap);
  ASSERT_EQ(faceMap.Extent(), topology.faceCount());
  ASSERT_EQ(edgeMap.Extent(), topology.edgeCount());
  for (int f = 0; f < topology.faceCount(); ++f) {
    EXPECT_TRUE(topology.face(f).IsSame(faceMap(f + 1))) << "face " << f;
    EXPECT_EQ(&topology.face(f), &solid->face(f));
  }
  for (int e = 0; e < topology.edgeCount(); ++e) {
    EXPECT_TRUE(topology.edge(e).IsSame(edgeMap(e + 1))) << "edge " << e;
    EXPECT_EQ(&topology.edge(e), &solid->edge(e));
    EXPECT_EQ(&topology.facesOfEdge(e), &solid->facesOfEdge(e));
  }
}

TEST(BrepTopology, ProjectsOntoAnEdgeAsTheSolid) {
  const std::shared_ptr<BrepSolid> solid = box();
  const BrepTopology& topology = *solid->brepTopology();
  // Below the box's edge x in [1, 11], y = 2, z = 3: sqrt(2) from it, at (6, 2, 3).
  const Point3 p{6, 1, 2};
  int nearest = -1;
  BoundaryProjection best;
  for (int e = 0; e < topology.edgeCount(); ++e) {
    const BoundaryProjection q = topology.projectOnEdge(p, e);
    const BoundaryProjection r = solid->projectOnEdge(p, e);
    EXPECT_EQ(q.point, r.point) << "edge " << e;
    EXPECT_EQ(q.distance, r.distance) << "edge " << e;
    EXPECT_EQ(q.patch, r.patch) << "edge " << e;
    EXPECT_EQ(q.patch, topology.facesOfEdge(e).front()) << "edge " << e;
    if (q.distance < best.distance) {
      best = q;
      nearest = e;
    }
  }
  ASSERT_GE(nearest, 0);
  EXPECT_NEAR(best.distance, std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(distance(best.point, Point3{6, 2, 3}), 0, 1e-9);
}

TEST(BrepTopology, OtherSourcesHaveNone) {
  const Sphere sphere({0, 0, 0}, 1, "ball");
  EXPECT_EQ(static_cast<const Source&>(sphere).brepTopology(), nullptr);
  // A tetrahedron, triangles oriented outward.
  const auto tetrahedron = TriangleSurface::fromTriangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                                                          {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, "tet");
  EXPECT_EQ(tetrahedron->brepTopology(), nullptr);
}

TEST(BrepTopology, OracleEntriesAnswerByKind) {
  const HierarchicalOracle oracle({{box(), Role::Material, 1},
                                   {std::make_shared<Sphere>(Point3{50, 0, 0}, 2, "ball"), Role::Material, 2}});
  const BrepTopology* first = oracle.entries()[0].source->brepTopology();
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->name(), "box");
  EXPECT_EQ(first->faceCount(), 6);
  EXPECT_EQ(oracle.entries()[1].source->brepTopology(), nullptr);
}

}  // namespace
}  // namespace oraclemesh
