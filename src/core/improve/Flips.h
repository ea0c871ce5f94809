#pragma once
// Topological flips (2-3 and 3-2) that raise the smallest dihedral angle of a tetrahedral
// mesh without moving a vertex. They need no Delaunay property, so they run on the final
// mesh of either engine.
#include <cstdint>

#include "mesh/TetMesh.h"

namespace oraclemesh {

struct FlipStats {
  double min_dihedral_before = 0;  // degrees
  double min_dihedral_after = 0;
  int64_t flips23 = 0;
  int64_t flips32 = 0;
  int passes = 0;
};

// Applies 2-3 and 3-2 flips, worst tetrahedron first, accepting a flip only when the
// smallest dihedral angle of the replaced tets strictly rises and every new tet is positively
// oriented by the exact predicate. Only faces and edges inside one material are removed:
// boundary / interface triangles, faces between two materials and feature edges
// (constrained subsegments) stay. No vertex moves, so volumes and the boundary are kept.
// Work is bounded by `max_passes` passes over the mesh (deterministic, not wall time); a pass
// with no flip ends early. Rejects second-order meshes (mid nodes would be stale).
FlipStats improveByFlips(TetMesh& mesh, int max_passes = 4);

}  // namespace oraclemesh
