#pragma once
// Puts the boundary nodes of an engine's mesh exactly onto the CAD geometry. Mesh_3 leaves
// boundary vertices within its bisection error of the surface. FreeCAD finds constraint nodes
// geometrically (1e-7 tolerance), so every boundary node is put exactly on the nearest B-rep
// face, and every feature node on its B-rep edge.
#include <cstdint>
#include <vector>

#include "Geometry.h"
#include "RunControl.h"
#include "domain/HierarchicalOracle.h"
#include "features/CurveRegistry.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

// What the snap did, for the report.
struct BoundarySnapStatistics {
  double max_move = 0;
  int64_t moved = 0;
  // Vertices left where Mesh_3 put them because the move would have flattened or inverted a
  // tet that could not be removed (interface slivers, where curves meet at small angles).
  int64_t kept_off_surface = 0;
  int64_t slivers_removed = 0;  // flat tets on the outer surface (see removeFlatSurfaceSlivers)
  int64_t slivers_kept_on_feature_edges = 0;  // flat ones kept: the last tet on a feature edge
  // Surface vertices the engine put exactly on a known entry's boundary (mesh.vertex_boundary_entry),
  // taken as they are instead of projected again.
  int64_t on_boundary_by_engine = 0;
  double max_distance_kept = 0;
  Point3 worst_kept{};
};

struct BoundarySnapResult {
  std::vector<int> vertex_entry;  // entry whose boundary the vertex was put on, -1 interior
  // Per vertex: how far from its place on the CAD the snap left it (0 for all it moved or
  // found there), so later checks allow that much at that vertex only.
  std::vector<double> distance_kept;
  BoundarySnapStatistics statistics;

  // The per-vertex data after vertices were removed or inserted (improveMesh's previousIndex:
  // each vertex's index before, -1 for an inserted interior one); an empty list changes nothing.
  void renumber(const std::vector<int64_t>& previousIndex);
};

// Mesh_3 leaves slivers lying on the outer surface (four corners on one face, or across a
// sharp edge) that go flat or inside out once their corners are on the CAD faces. Such a tet
// with two or three faces on the outside holds no volume of the part: removing it leaves its
// other faces as the (equally flat) surface there. Interface slivers are not removed (that
// would open the interface); the snap leaves their corners where they are instead. Nor is the
// last tet on a feature edge (the edge would leave the mesh; thesis cells labelled by their
// barycentre at a convex edge are such tets): counted in `keptOnFeatureEdges`.
// `target`: where each vertex is about to go. Returns the number of tets removed.
int64_t removeFlatSurfaceSlivers(TetMesh& mesh, const std::vector<Point3>& target, int64_t& keptOnFeatureEdges);

// Moves every vertex on mesh.boundary (which must be current) or on a feature curve onto its
// curve (`curves`), else onto the nearest boundary of the oracle, unless the move would
// flatten or invert one of its tets; removes the flat surface slivers first. Vertices of
// dimension 3 on the boundary become dimension 2. Checks for cancellation.
BoundarySnapResult snapBoundaryVertices(TetMesh& mesh, const HierarchicalOracle& oracle, const CurveRegistry& curves,
                                        const RunControl& control);

}  // namespace oraclemesh
