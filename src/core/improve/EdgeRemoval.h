#pragma once
// Edge removal (Shewchuk 2002, "Two discrete optimization algorithms for the topological
// improvement of tetrahedral meshes"; Klingner and Shewchuk 2007): the n tets around an
// interior edge ab (n = 3..7, one material, a closed ring r_0..r_{n-1}) are replaced by the
// 2(n-2) tets that join a triangulation of the ring to a and to b. The triangulation is the
// one whose worst tet is best, found by dynamic programming over the ring's sub-polygons.
// n = 3 is the 3-2 flip, n = 4 the 4-4 flip.
#include <array>
#include <cstdint>
#include <vector>

#include "improve/ImprovementMesh.h"
#include "improve/SizeCriteria.h"

namespace oraclemesh {

inline constexpr int kMaxEdgeRemovalRing = 7;

// Removes edge ab when that raises the smallest dihedral angle of the tets around it, every
// new tet is positively oriented (exact predicate) and within the size of the worst old one or
// the job's `sizes` (SizeBound). Never removes a feature edge, an edge on a boundary or
// interface triangle, or an edge whose tets are of several materials. Returns the ring size
// when removed, else 0.
int removeEdge(ImprovementMesh& mesh, int64_t a, int64_t b, const SizeCriteria& sizes = SizeCriteria{});

// The best triangulation of the closed ring of `tets` around ab (3..7 of them, whatever their
// materials and faces): the tets it makes, every one positive and admitted by `bound` as tets
// of `material`, no ring diagonal already a mesh edge. Returns the smallest dihedral angle of
// those tets, or -infinity (and `made` unspecified) when there is no such triangulation.
double triangulateEdgeRing(const ImprovementMesh& mesh, int64_t a, int64_t b, const std::vector<int64_t>& tets,
                           const SizeBound& bound, int material, std::vector<TetCorners>& made);

// The same for the tets on one side of an edge ab of the boundary or of an interface (2..6 of
// them, an open fan from link vertex ends[0] to ends[1]): the best triangulation of the fan's
// polygon closed by the new edge ends[0] ends[1], which with a and b makes the two triangles
// that replace the fan's two faces on the surface (SurfaceFlip.h).
double triangulateEdgeFan(const ImprovementMesh& mesh, int64_t a, int64_t b, const std::vector<int64_t>& tets,
                          const SizeBound& bound, int material, std::vector<TetCorners>& made,
                          std::array<int64_t, 2>& ends);

}  // namespace oraclemesh
