#pragma once
// Vertex insertion (Klingner and Shewchuk 2007 use it where flips and smoothing are stuck): a
// new vertex inside one material replaces the tets around it by its star. The cavity is the
// tets whose circumsphere holds the new point (Bowyer-Watson), reached from the tet that holds
// it across faces that are no boundary or interface triangle, between tets of its material.
// The mesh is not Delaunay, so the cavity is checked, not trusted: the star must fill exactly
// the cavity with positive tets and keep every vertex, feature edge and protected face. The
// smoothing sweeps then move the new vertex like any other interior one.
#include <cstdint>

#include "improve/ImprovementMesh.h"
#include "improve/SizeCriteria.h"

namespace oraclemesh {

// At most this many tets are replaced by one insertion.
inline constexpr int kMaxInsertionCavity = 48;

// Tries a new interior vertex for tet t at its centroid, its circumcentre and the midpoints of
// its edges that are no feature edge, and keeps the point whose star's smallest dihedral angle
// is best, when that beats the cavity's tets, every new tet is positive (exact predicate) and
// within the size of the worst old one or the job's `sizes` (SizeBound), and the star holds the
// cavity's volume. Returns the new vertex, or -1 when nothing changed.
int64_t insertVertex(ImprovementMesh& mesh, int64_t t, const SizeCriteria& sizes = SizeCriteria{});

}  // namespace oraclemesh
