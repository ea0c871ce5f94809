#pragma once
// Flat tets lying on a planar piece of the boundary or of an interface, with two of their
// faces on it (a "flat cap": the two faces and the two inner ones are the two triangulations
// of the same planar quad). No operation that keeps the boundary triangles can remove them;
// these do, keeping the geometry: on the outer boundary the tet is taken out (its inner faces
// become the boundary, the same quad); on an interface between materials A and B, the A tet is
// given to B and the ring of tets around its edge on the interface re-triangulated, which is
// the 2-2 flip of the two interface triangles done on both sides. No vertex moves.
// A flat tet with three faces on the outer boundary (a fold: the surface there is folded over
// itself, both triangulations of a quad at once, or pinched at a corner) is taken out the same
// way: its fourth face becomes the boundary.
#include <cstdint>

#include "mesh/TetMesh.h"

namespace oraclemesh {

struct FlatCapStats {
  int64_t boundary_caps_removed = 0;  // outer boundary: tet taken out
  int64_t interface_caps_flipped = 0; // interface: tet given to the other side, its ring re-triangulated
  int64_t folds_removed = 0;          // outer boundary: flat tets with three faces on it, taken out
  int64_t caps_kept = 0;              // flat caps and folds a condition kept (feature edge, manifold, volume, orientation)
  double largest_volume_change = 0;   // over the materials: summed volume moved / material volume
  int64_t curved_caps = 0;            // of the changes, caps on curved pieces
  double largest_curved_volume_change = 0;  // the same share for those
};

// Caps lying on a curved piece of the boundary or an interface (slivers whose four corners
// are on one curved face): flat within `relative_flatness` of their longest edge instead of
// the absolute flatness. Their change takes the sliver's volume from one side (a chord of the
// face replaces another), counted apart within `volume_bound` of each material's volume.
// relative_flatness 0: none.
struct CurvedCapLimits {
  double relative_flatness = 0;
  double volume_bound = 0;
};

// Flat means every corner within `flatness` (absolute length) of one plane, the two cap faces
// facing one way and the two inner faces the other. Conditions for a change: the edge the
// change removes is no feature edge (a fold: no edge at its corner is a feature edge only it
// has, and the corner's other tets are one fan), the new boundary edge was on no boundary or interface
// before (the surface stays manifold), every vertex stays in a tet, every new tet is
// positive (exact predicate) and no worse than the flat one, and the volume each material
// gains or loses, summed over the changes, stays within `volume_bound` of its volume. Rebuilds
// mesh.boundary when it changes anything. Deterministic: tets are taken in index order.
FlatCapStats removeFlatCaps(TetMesh& mesh, double flatness, double volume_bound, const CurvedCapLimits& curved = {});

}  // namespace oraclemesh
