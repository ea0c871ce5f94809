#pragma once
// Optimisation-based vertex smoothing (after Freitag and Ollivier-Gooch 1997, as Klingner and
// Shewchuk 2007 use it): a vertex moves to raise the smallest dihedral angle of its tets, by
// line searches along the ascent direction of that worst angle. Interior vertices move
// freely; vertices inside a planar boundary patch move in its plane and vertices inside a
// straight feature curve along its line (so each stays on its CAD face or edge and no
// material gains or loses volume). With the mesh's BoundaryPlacement, vertices inside a curved
// patch move in its tangent plane and vertices inside a curved feature curve along their
// chord, each step put back onto the face or curve; the volume this moves between a material
// and its outside is bounded (ImprovementMesh::volumeFits). All others stay.
#include <cstdint>

#include "improve/ImprovementMesh.h"
#include "improve/SizeCriteria.h"

namespace oraclemesh {

// Moves vertex v when that strictly raises the smallest dihedral angle of its tets, keeps
// every one of them positively oriented (exact predicate), none bigger than the worst of them
// before, and no boundary triangle or feature edge at v bigger than the biggest before unless
// within `sizes` (a feature edge within the edge size, a planar patch's triangle within the
// facet size). Returns whether it moved.
bool smoothVertex(ImprovementMesh& mesh, int64_t v, const SizeCriteria& sizes = {});

}  // namespace oraclemesh
