#pragma once
// TP, the planar-face layer (thesis §4.1, "planar input polygons", left unfinished there; job
// option features.planar_faces), between T1 and T2:
//   TP   a triangle of the 2D Delaunay triangulation of the vertices on a planar face's plane,
//        restricted to the face (PlanarFacets.h), is no facet of the 3D triangulation:
//        TP.1 its circumcentre encroaches a subsegment -> split the subsegment (as T2.1);
//        TP.2 else insert the circumcentre if it lies on the face.
// The 2D triangulations are rebuilt when the other queues are empty (rebuilding them after
// every insertion would cost more than the refinement); the triangles found missing then go
// before T2 and T3. Cells with an edge on a planar face take their material from the
// barycentre: a flat cell on the face may have its circumcentre across the plane. The layer
// meets the core only through RefinementHook.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {

class PlanarFaceLayer : public RefinementHook {
 public:
  explicit PlanarFaceLayer(RuleSetTRefiner& core) : core_(core), faces_(core.options().planar_faces) {}

  // Records on which planar faces' planes a new vertex lies (within the oracle tolerance:
  // exact crossings, splits of straight segments and circumcentres put there all do).
  void vertexAdded(VH v) override;
  // A cell with an edge on a face.
  bool labelsByBarycentre(CH c) const override;
  // A cell with its four corners on one face.
  bool hasUndefinedCircumsphere(CH c) const override { return faceOfCell(c) >= 0; }
  bool refineOne() override;
  bool queuesEmptied() override;
  // Counts the triangles recovered and lists those missing (statistics.planar).
  void refinementDone() override;
  const char* checkPhase() const override { return "planar_check"; }
  // Vertices on a face's plane stay where they are, so the face's 2D triangulation and its
  // recovery hold after rule P.
  bool pinsVertex(VH v) const override;

 private:
  struct QueuedTriangle {
    int face = -1;
    std::array<VH, 3> corners;
    Point3 circumcentre{};
    double radius = 0;
    size_t pointsAtCheck = 0;  // vertices on the face when the triangle was found
    CH flatCell;               // set for a flat cell on the face (its circle centre goes in)
    uint64_t flatStamp = 0;
  };

  int faceOfCell(CH c) const;
  static std::array<int64_t, 3> cornerKey(const std::array<VH, 3>& corners);
  bool isFacet(const std::array<VH, 3>& corners) const;
  std::vector<QueuedTriangle> triangles(size_t f, bool missingOnly) const;
  bool triangleGone(const QueuedTriangle& t) const;

  RuleSetTRefiner& core_;
  const std::vector<PlanarFace>& faces_;
  // The vertices on each face's plane (by face, in insertion order), the faces each vertex
  // lies on (by vertex id), the triangles found missing, and why the ones given up on were left.
  std::vector<std::vector<VH>> vertices_;
  std::vector<std::vector<int>> facesOfVertex_;
  std::vector<QueuedTriangle> queue_;
  std::map<std::array<int64_t, 3>, std::string> left_;
  int64_t verticesAtCheck_ = -1;
  bool checked_ = false;
};

}  // namespace oraclemesh::refine
