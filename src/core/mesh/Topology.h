#pragma once
// Connectivity of a TetMesh: its material boundary and the checks that tell a solver-ready
// mesh from a broken one (non-manifold faces, holes in a material's boundary, folded tets,
// tet10 mid nodes that neighbouring tets do not share).
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "mesh/TetMesh.h"

namespace oraclemesh {

// Throws oraclemesh::Error if the arrays of `mesh` do not fit together (a tet or triangle
// index out of range, one material per tet missing, a per-vertex array of the wrong length).
// Such a mesh is a bug upstream; every function of mesh/ calls this before reading indices.
void requireConsistentIndices(const TetMesh& mesh);

// An undirected edge (a, b) as one key (point indices below 2^32).
inline uint64_t undirectedEdgeKey(int64_t a, int64_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | static_cast<uint64_t>(b);
}

// Feature edges of `mesh` that are no edge of any of its tets (0 when every constrained
// subsegment is a mesh edge); `first`, if given, gets the index of the first such edge.
int64_t featureEdgesNotTetEdges(const TetMesh& mesh, size_t* first = nullptr);

// The final check of every mesh a job returns: a feature edge is a constrained segment the
// job asked to keep (a sharp edge, a junction, a polyline), and FreeCAD finds its mid node
// and draws it from the tets' edges. Throws oraclemesh::Error (an internal error naming the
// count and the first such edge) when one is no tet edge: no phase may drop one silently.
void requireFeatureEdgesInTets(const TetMesh& mesh);

// Every tet face on the material boundary, once: faces with a tet on one side only (the
// outside, material_out = 0) and faces between tets of different materials.
//  - Orientation: the normal (v1-v0)x(v2-v0) points out of the tet the triangle is taken from,
//    which is the material_in side (outward from the domain on the outer boundary).
//  - Interfaces between materials a < b: ONE triangle, taken from the tet of material a, so
//    material_in = a (the smaller id), material_out = b, normal pointing from a into b.
//  - Order: deterministic, by the first tet (in tets order) that has the face.
//  - Faces shared by more than two tets are not part of a valid mesh and are left out;
//    checkConformity counts them.
std::vector<BoundaryTriangle> extractBoundary(const TetMesh& mesh);

// extractBoundary's faces, in its order, as element faces: the tet each is taken from and the
// corner of that tet the face is opposite to (for writers that name faces per element).
// Interface faces also name the tet on the other side (the larger material's), so that a
// surface can be taken from either side.
struct BoundaryFace {
  int64_t tet = 0;
  int opposite_corner = 0;
  int material_out = 0;  // 0 = outside the domain
  int64_t other_tet = -1;          // -1 on the outside
  int other_opposite_corner = -1;
};
std::vector<BoundaryFace> boundaryElementFaces(const TetMesh& mesh);

struct ConformityReport {
  int64_t faces_shared_by_more_than_two = 0;
  // Edges of one material's boundary used by an odd number of that material's boundary
  // triangles: the region has a hole (each material is checked on its own, because an edge
  // where three materials meet legitimately has three boundary triangles).
  int64_t open_boundary_edges = 0;
  // Tets with corner volume <= 0; for second order also tets whose Jacobian determinant is
  // <= 0 at a corner or the centroid (curved edges that fold the element).
  int64_t inverted_tets = 0;
  int64_t unused_points = 0;  // points that no tet uses as a corner or mid node
  // Second order only: tet edges whose tets disagree on the mid node, plus mid nodes that
  // serve more than one edge or are also a corner.
  int64_t inconsistent_mid_nodes = 0;

  bool ok() const {
    return faces_shared_by_more_than_two == 0 && open_boundary_edges == 0 && inverted_tets == 0 &&
           unused_points == 0 && inconsistent_mid_nodes == 0;
  }
};

ConformityReport checkConformity(const TetMesh& mesh);

// Per material, the pieces its tetrahedra form when tets sharing a face are joined, and pieces
// sharing three nodes not on one line (rigidly attached) too.
std::map<int, int64_t> componentsPerMaterial(const TetMesh& mesh);

}  // namespace oraclemesh
