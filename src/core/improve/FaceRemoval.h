#pragma once
// Multi-face removal (Shewchuk 2002, "Two discrete optimization algorithms for the topological
// improvement of tetrahedral meshes"), the inverse of edge removal: faces sandwiched between
// two apexes (each face has a tet with the one and a tet with the other, all of one material)
// that form a disk with every vertex on its rim are replaced by the edge between the apexes
// and one tet per rim edge. One face is the 2-3 flip.
#include <cstdint>

#include "improve/ImprovementMesh.h"
#include "improve/SizeCriteria.h"

namespace oraclemesh {

// At most this many sandwiched faces are searched from the first one.
inline constexpr int kMaxRemovedFaces = 16;

// Removes face abc and, where that gives a better result, sandwiched faces around it, all
// reached across edges that are no feature edge, faces that are no boundary or interface
// triangle. The chosen disk is the one whose worst new tet is best (dynamic programming over
// the tree of sandwiched faces); it is taken when every new tet is positive (exact predicate)
// and within the size of the worst old one or the job's `sizes` (SizeBound), and their
// smallest dihedral angle beats that of the old tets. Returns the number of faces removed (0:
// nothing changed).
int removeFaces(ImprovementMesh& mesh, int64_t a, int64_t b, int64_t c, const SizeCriteria& sizes = SizeCriteria{});

}  // namespace oraclemesh
