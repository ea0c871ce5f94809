#pragma once
// Connectivity of a TetMesh: its material boundary and the checks that tell a solver-ready
// mesh from a broken one (non-manifold faces, holes in a material's boundary, folded tets,
// tet10 mid nodes that neighbouring tets do not share).
#include <cstdint>
#include <vector>

#include "mesh/TetMesh.h"

namespace oraclemesh {

// Throws oraclemesh::Error if the arrays of `mesh` do not fit together (a tet or triangle
// index out of range, one material per tet missing, a per-vertex array of the wrong length).
// Such a mesh is a bug upstream; every function of mesh/ calls this before reading indices.
void requireConsistentIndices(const TetMesh& mesh);

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

// After a step that rebuilt `to` from `from` and may have moved or renumbered points (CGAL's
// sliver perturbation): each point of `to` gets the vertex_boundary_entry of the point of
// `from` at exactly the same coordinates, -1 where none is (a moved point is no longer known
// to be on that boundary). Empty when `from` has none. Only exact coordinates are trusted.
void carryBoundaryEntries(const TetMesh& from, TetMesh& to);

}  // namespace oraclemesh
