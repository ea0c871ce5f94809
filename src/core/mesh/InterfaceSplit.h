#pragma once
// Gives parts that are not bonded their own nodes along the faces (edges, vertices) they
// share: the mesh step behind the tied, contact and separate interfaces (issue 19).
#include <cstdint>

#include "mesh/InterfaceKinds.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

struct InterfaceSplitStats {
  int64_t corner_copies = 0;  // new points for tet corners
  int64_t mid_copies = 0;     // new points for tet10 mid nodes
};

// Per corner node: the materials of the tets around it, joined into classes by the bonded
// pairs among them (union-find; so three parts bonded in a ring stay joined at a node all
// three share even when one pair of them is not bonded). The class holding the smallest
// material keeps the node, every other class gets a copy (appended, in node order, then
// class order) and its tets are rewired to it. Mid nodes then follow their edge: the tets
// using one mid node are grouped by the (new) corners of that edge, and each group after the
// first (in tet order) gets a copy, so tets sharing an edge always share its mid node.
//  - Tets keep their index, order, material and orientation: element faces found before the
//    split (meshSurfaces) name the same faces after it.
//  - Copies keep the coordinates (nodes stay on the CAD) and the per-vertex data of their
//    original (vertex_dimension, vertex_curve, vertex_boundary_entry, vertex_weights).
//  - Boundary triangles take the copies of their material_in side. A feature edge becomes
//    one edge per distinct pair of new ends that tets have it with (the first in its place,
//    the others appended with the same curve id), so every feature edge stays a tet edge.
//  - Nothing changes when every pair present is bonded; deterministic.
InterfaceSplitStats splitInterfaces(TetMesh& mesh, const InterfacePlan& plan);

}  // namespace oraclemesh
