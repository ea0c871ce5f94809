#pragma once
// Edge collapse (Klingner and Shewchuk 2007 use it where flips and smoothing cannot help): a
// vertex v goes onto a neighbour u along their edge, the tets having both go, and v's other
// tets have u for v. It takes out the short edges that make slivers when neither end can move
// far enough. v may go onto u only where that keeps it in its place in the model:
//   - v interior (Free): onto any neighbour;
//   - v inside a planar patch (Planar): onto a corner of one of its boundary triangles, which
//     lies in the patch's plane, so the patch and every material's volume stay as they are;
//   - v inside a straight feature curve (Linear): onto one of its two curve neighbours, when
//     the merged curve segment is within the edge size there;
//   - v on a curved patch or curve (Curved, OnCurve): the same, u then being another point of
//     the face or curve; the chords change, so each material's volume does, within what is
//     left of the stage's curved-move bound (ImprovementMesh::volumeFits).
// Fixed vertices (corners, vertices of several interfaces) stay.
#include <cstdint>

#include "improve/ImprovementMesh.h"
#include "improve/SizeCriteria.h"

namespace oraclemesh {

// Collapses v onto u when it is allowed (above), the result is a mesh (the link condition of
// the tets closed by a vertex at infinity, of the boundary and interface triangles, and of the
// feature edges), every changed tet is positive (exact predicate), within the radius-edge ratio
// of the worst tet at v and within the circumradius of the largest or the job's cell size,
// every renamed boundary triangle within the facet size (SizeCriteria), and the smallest
// dihedral angle of the changed tets is above that of v's tets before.
bool collapseEdge(ImprovementMesh& mesh, int64_t v, int64_t u, const SizeCriteria& sizes = {});

}  // namespace oraclemesh
