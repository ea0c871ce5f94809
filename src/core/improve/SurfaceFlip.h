#pragma once
// The 2-2 flip of two surface triangles: the boundary or interface triangles abc and abd,
// forming a convex quad, become acd and bcd, and the tets on each side of ab (an open fan from
// c to d) are replaced by the best triangulation of that fan without ab (EdgeRemoval.h's
// triangulateEdgeFan, once per side). It lifts tets whose bad shape comes from the surface
// triangulation itself, which no operation that keeps the boundary triangles can change (a
// short surface edge across a long thin pair of triangles). In a plane the surface stays the
// same plane piece and no material gains or loses volume; on a curved face (nearly flat
// there) one chord replaces another, and the sliver abcd changes sides.
#include <cstdint>

#include "improve/ImprovementMesh.h"
#include "improve/SizeCriteria.h"

namespace oraclemesh {

// Flips ab when: ab is no feature edge and lies on exactly two protected faces abc and abd;
// the tets around ab are of one material (outer boundary) or two (an interface), 2..6 on
// each side; a, b, c, d lie in one plane (within 1e-9 of the quad's longest edge, the snap's
// rounding) or, when the mesh has a BoundaryPlacement (its vertices are on the CAD), within
// `curvedFlatness` of that edge; acbd is convex; cd is no mesh edge yet; every new tet is
// positive (exact predicate) and within SizeBound of its side's old tets; in a plane the new
// triangles are no larger in circumradius than the larger old one or within the job's facet
// size; on a curved piece cd is no longer than ab and each material's volume change stays
// within the mesh's curved-move bound (ImprovementMesh::volumeFits); and the smallest dihedral
// angle of the tets around ab strictly rises. Returns whether it flipped.
bool flipSurfaceEdge(ImprovementMesh& mesh, int64_t a, int64_t b, const SizeCriteria& sizes = SizeCriteria{},
                     double curvedFlatness = 0);

}  // namespace oraclemesh
