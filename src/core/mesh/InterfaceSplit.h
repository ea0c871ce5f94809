#pragma once
// Gives parts that are not bonded their own nodes along the faces (edges, vertices) they
// share: the mesh step behind the tied, contact and separate interfaces (issue 19).
#include <cstdint>
#include <map>
#include <set>
#include <utility>

#include "mesh/InterfaceKinds.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

// A pair that is not bonded but keeps corner nodes in common: where both parts meet a third
// one bonded to each (A-B and B-C bonded, A-C not), a node they all share cannot be split
// between A and C without splitting it from B too.
struct KeptJoined {
  int64_t nodes = 0;      // corner nodes the pair still shares
  std::set<int> through;  // the materials bonded to both there
};

struct InterfaceSplitStats {
  int64_t corner_copies = 0;  // new points for tet corners
  int64_t mid_copies = 0;     // new points for tet10 mid nodes
  std::map<std::pair<int, int>, KeptJoined> kept_joined;  // key: (smaller, larger material id)
};

// Per corner node: the materials of the tets around it, joined into classes by the bonded
// pairs among them (union-find; so three parts bonded in a ring stay joined at a node all
// three share even when one pair of them is not bonded). The class holding the smallest
// material keeps the node, every other class gets a copy (appended, in node order, then
// class order) and its tets are rewired to it. Mid nodes then follow their edge: the tets
// using one mid node are grouped by the (new) corners of that edge, and each group after the
// first (in tet order) gets a copy, so tets sharing an edge always share its mid node.
// Pairs left sharing nodes that way are counted in kept_joined.
//  - Tets keep their index, order, material and orientation: element faces found before the
//    split (meshSurfaces) name the same faces after it.
//  - Copies keep the coordinates (nodes stay on the CAD) and the per-vertex data of their
//    original (vertex_dimension, vertex_curve, vertex_boundary_entry).
//  - Boundary triangles take the copies of their material_in side. A feature edge becomes
//    one edge per distinct pair of new ends that tets have it with (the first in its place,
//    the others appended with the same curve id), so every feature edge stays a tet edge.
//  - Nothing changes when every pair present is bonded; deterministic.
InterfaceSplitStats splitInterfaces(TetMesh& mesh, const InterfacePlan& plan);

}  // namespace oraclemesh
