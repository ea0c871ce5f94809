#pragma once
// The tetrahedral mesh as the improvement operations change it: tets that can be removed and
// added, each vertex's tets, the faces and edges no operation may remove, and how far each
// vertex may move. It works on a copy of the tets and in place on the points of a linear
// TetMesh; writeBack puts the surviving and new tets back in a deterministic order, and drops
// the vertices edge collapses removed.
#include <array>
#include <cstdint>
#include <map>
#include <unordered_set>
#include <vector>

#include "improve/BoundaryPlacement.h"
#include "improve/TetShape.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

// How a vertex may move without leaving its place in the model.
enum class VertexFreedom {
  Fixed,   // corners, vertices of several interfaces; curved ones without a BoundaryPlacement
  Free,    // interior of one material
  Planar,  // inside a planar patch of the boundary: in that plane
  Linear,  // inside a straight feature curve: along its line
  Curved,  // inside a curved patch of one interface: in its tangent plane, then back onto it
  OnCurve, // inside a curved feature curve: along its chord, then back onto the curve
};

struct VertexMobility {
  VertexFreedom freedom = VertexFreedom::Fixed;
  Point3 axis{};  // unit normal of the plane (Planar) or direction of the line (Linear)
  // What bounds the move besides the tets: the boundary triangles at the vertex (Planar,
  // Curved, OnCurve), whose circumradius the facet size bounds, and the two ends of its feature
  // edges (Linear, OnCurve), whose length the edge size bounds.
  std::vector<std::array<int64_t, 3>> boundary_triangles;
  std::array<int64_t, 2> feature_neighbours{-1, -1};
};

class ImprovementMesh {
 public:
  // With `placement`, vertices on curved patches and curves move too (Curved, OnCurve); each
  // material's volume may then change, by at most `curvedVolumeBound` of it net: a vertex moved
  // from one point of a curved face to another changes the chords, not the face, and the
  // changes of many moves over a face's convex and concave stretches largely cancel. (Bounding
  // their absolute sum instead stopped the stage long before the angles were reached.)
  explicit ImprovementMesh(TetMesh& mesh, const BoundaryPlacement* placement = nullptr, double curvedVolumeBound = 0);

  std::vector<Point3>& points() { return points_; }
  const std::vector<Point3>& points() const { return points_; }
  const TetCorners& tet(int64_t t) const { return tets_[t]; }
  int material(int64_t t) const { return materials_[t]; }
  bool alive(int64_t t) const { return alive_[t]; }
  int64_t tetSlots() const { return static_cast<int64_t>(tets_.size()); }
  const std::vector<int64_t>& tetsOf(int64_t v) const { return vertex_tets_[v]; }
  const VertexMobility& mobility(int64_t v) const { return mobility_[v]; }
  const BoundaryPlacement* placement() const { return placement_; }

  // Whether each material's net volume change, with `change` (material -> signed volume) added,
  // stays within its bound; addVolumeChange adds them.
  bool volumeFits(const std::map<int, double>& change) const;
  void addVolumeChange(const std::map<int, double>& change);
  // The largest share of a material's volume by which the moves so far changed it (net).
  double largestVolumeShareChanged() const;

  // Alive tets having both ends of the edge / all three corners of the face.
  std::vector<int64_t> tetsAroundEdge(int64_t a, int64_t b) const;
  std::vector<int64_t> tetsWithFace(int64_t a, int64_t b, int64_t c) const;
  bool hasEdge(int64_t a, int64_t b) const;

  bool isProtectedEdge(int64_t a, int64_t b) const;  // a feature edge (constrained subsegment)
  bool isProtectedFace(int64_t a, int64_t b, int64_t c) const;  // a boundary or interface triangle

  double quality(int64_t t) const { return smallestDihedral(points_, tets_[t]); }

  // When the neighbourhood of a vertex last changed (a tet of it replaced, it or a neighbour
  // moved), on a counter of changes: lets the driver skip what it tried since.
  int64_t changedAt(int64_t v) const { return changed_at_[v]; }
  int64_t now() const { return clock_; }
  // Marks v and every vertex of its tets changed (after moving v).
  void markMoved(int64_t v);

  // Removes `old` and adds `made` (all of `material`); returns the new tets' indices.
  std::vector<int64_t> replace(const std::vector<int64_t>& old, const std::vector<TetCorners>& made, int material);

  // Edge collapse (EdgeCollapse.h, which decides whether it is allowed): v goes onto u. Each
  // tet of v without u becomes `made` (v renamed u, same material); the tets having both go.
  // Protected faces and edges at v are renamed and those having both go; v is left with no tet.
  void collapse(int64_t v, int64_t u);
  // A 2-2 flip on the surface (SurfaceFlip.h, which replaces the tets): the protected faces abc
  // and abd become acd and bcd, here and in the boundary triangles that bound the four
  // vertices' moves; writeBack then extracts the boundary again.
  void flipProtectedFaces(int64_t a, int64_t b, int64_t c, int64_t d);
  bool removed(int64_t v) const { return collapsed_into_[v] >= 0; }
  int64_t removedVertexCount() const { return removed_vertices_; }
  // A new interior vertex (Free) at p, in no tet yet: vertex insertion (VertexInsertion.h)
  // gives it its star with replace().
  int64_t addVertex(const Point3& p);
  // The faces (sorted corners) of the alive tets at v that have v; those of them no other
  // alive tet has (on the outer boundary).
  std::vector<std::array<int64_t, 3>> facesAt(int64_t v) const;
  std::vector<std::array<int64_t, 3>> outerFacesAt(int64_t v) const;

  // The alive tets in index order (originals first, then the ones the operations made), and the
  // boundary extracted again when a surface flip changed it. Inserted vertices come after the
  // mesh's own (interior: dimension 3, no curve, no boundary entry). When vertices were removed
  // or inserted, the mesh's points and per-vertex data are renumbered without the removed ones,
  // its feature edges renamed and its boundary extracted again; the result gives each written
  // vertex's index before, -1 for an inserted one (empty: none removed or inserted, numbering
  // unchanged).
  std::vector<int64_t> writeBack(TetMesh& mesh) const;

 private:
  struct KeyHash {
    size_t operator()(const std::array<int64_t, 3>& k) const {
      return static_cast<size_t>(k[0] * 73856093 ^ k[1] * 19349663 ^ k[2] * 83492791);
    }
  };
  static std::array<int64_t, 3> faceKey(int64_t a, int64_t b, int64_t c);
  void classifyVertices(const TetMesh& mesh);

  std::vector<Point3>& points_;
  std::vector<TetCorners> tets_;
  std::vector<int> materials_;
  std::vector<char> alive_;
  std::vector<std::vector<int64_t>> vertex_tets_;
  std::unordered_set<std::array<int64_t, 3>, KeyHash> protected_faces_;
  std::unordered_set<std::array<int64_t, 3>, KeyHash> protected_edges_;  // (a, b, -1), a < b
  std::vector<VertexMobility> mobility_;
  const BoundaryPlacement* placement_ = nullptr;
  double curved_volume_bound_ = 0;
  std::map<int, double> material_volume_;
  std::map<int, double> volume_change_;  // per material, net, signed
  std::vector<int64_t> changed_at_;
  int64_t clock_ = 0;
  std::vector<int64_t> collapsed_into_;  // per vertex: the vertex it went onto, -1 kept
  int64_t removed_vertices_ = 0;
  int64_t added_vertices_ = 0;
  bool surface_flipped_ = false;
  size_t original_vertices_ = 0;
};

}  // namespace oraclemesh
