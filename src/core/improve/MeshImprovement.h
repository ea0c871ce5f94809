#pragma once
// The improvement stage: topological operations (edge removal incl. 3-2 and 4-4, multi-face
// removal incl. 2-3 flips, 2-2 flips of surface triangles, edge collapse, vertex
// insertion) and vertex smoothing, worst tet first, repeated in passes. Every operation raises
// the smallest dihedral angle of the tets it replaces or moves, so the mesh is the best so far
// after each one and can be stopped anywhere. It runs on the final linear mesh of either
// engine, needs no Delaunay property, and keeps: positive tets (exact orientation), the surface
// (boundary and interface triangles change only by flips of nearly flat quads, FlatCaps.h and
// SurfaceFlip.h, exactly in place in planes), every feature edge, each tet's material, per-material volumes (exactly where
// vertices move inside planar patches and along straight curves; within `curved_volume_bound`
// where they move on curved faces and curves), and the size criteria (no new tet bigger in
// circumradius or radius-edge ratio than the worst it replaces, unless within the job's
// criteria of its material: SizeBound).
#include <cstdint>
#include <vector>

#include "RunControl.h"
#include "improve/BoundaryPlacement.h"
#include "improve/FlatCaps.h"
#include "improve/SizeCriteria.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

struct ImprovementOptions {
  double goal_deg = 20;   // tets whose smallest dihedral angle is below it are worked on
  int max_passes = 8;     // the deterministic work bound; a pass that changes nothing ends it
  double time_limit = 0;  // seconds, 0 = none (a wall-time stop makes the mesh machine-dependent)
  // Flat caps on planar boundary and interface pieces (FlatCaps.h), before the other operations:
  // flat within this fraction of the mesh's bounding-box diagonal (the boundary snap's
  // tolerance), at most this fraction of a material's volume moved in all.
  bool flat_caps = true;
  double flat_cap_flatness = 1e-9;
  double flat_cap_volume_bound = 1e-9;
  // Puts vertices moved on curved faces and curves back onto them; null: those stay.
  const BoundaryPlacement* placement = nullptr;
  // The share of each material's volume by which such moves may change it (net, ImprovementMesh.h);
  // caps on curved pieces (FlatCaps.h, with a placement only) get the same share apart.
  double curved_volume_bound = 1e-5;
  // A cap or a surface flip on a curved piece: its corners within this share of its longest
  // edge of one plane.
  double curved_cap_flatness = 0.05;
  // 2-2 flips of surface triangles (SurfaceFlip.h) where the interior operations cannot help a
  // tet: in planar pieces, and with a placement on nearly flat stretches of curved ones.
  bool surface_flips = true;
  // Edge collapse (EdgeCollapse.h) where edge removal and flips cannot help a tet.
  bool edge_collapse = true;
  // Vertex insertion (VertexInsertion.h), in passes of their own after the others: insertion,
  // then the other operations around the new vertices; a pass inserting nothing ends them.
  bool vertex_insertion = true;
  int insertion_passes = 4;
  // The job's edge, facet and cell sizes and ratio bound, which every operation keeps where it
  // lengthens a feature edge or enlarges a boundary triangle or a tet (SizeCriteria.h).
  SizeCriteria sizes;
};

struct PoorTetCounts {
  int64_t under5 = 0, under10 = 0, under15 = 0;  // tets by smallest dihedral angle, degrees
};

struct ImprovementStats {
  double min_dihedral_before = 0;  // degrees
  double min_dihedral_after = 0;
  PoorTetCounts before, after;
  int64_t flips23 = 0;             // face removal of one face
  int64_t multi_face_removals = 0;  // of several
  int64_t flips32 = 0;           // edge removal with a ring of 3
  int64_t flips44 = 0;           // ring of 4
  int64_t edge_removals = 0;     // rings of 5 to 7
  int64_t surface_flips = 0;     // 2-2 flips of boundary or interface triangles
  int64_t edge_collapses = 0;    // vertices removed
  int64_t vertex_insertions = 0;  // interior vertices added
  // Where the other operations left the mesh, before the insertion passes.
  double min_dihedral_before_insertion = 0;
  PoorTetCounts before_insertion;
  int64_t smoothed_interior = 0;
  int64_t smoothed_surface = 0;  // in a planar patch
  int64_t smoothed_feature = 0;  // along a straight curve
  int64_t smoothed_curved_surface = 0;  // on a curved face, put back onto it
  int64_t smoothed_curved_feature = 0;  // on a curved curve, put back onto it
  double curved_volume_share = 0;       // the largest share of a material's volume those changed (net)
  FlatCapStats flat_caps;
  int passes = 0;
  bool stopped_by_time_limit = false;
  double seconds = 0;
};

// Rejects second-order meshes (mid nodes would be stale). Checks `control` for cancellation.
// Rebuilds mesh.boundary when flat caps, surface flips, collapses or insertions change it.
// Edge collapses remove vertices and insertions add interior ones after the others: the mesh is
// renumbered, and `previousIndex` (when given) gets each vertex's index before the stage (-1 for an
// inserted one), so that per-vertex data kept elsewhere can follow (left empty when the
// numbering did not change).
ImprovementStats improveMesh(TetMesh& mesh, const ImprovementOptions& options, const RunControl& control,
                             std::vector<int64_t>* previousIndex = nullptr);

}  // namespace oraclemesh
