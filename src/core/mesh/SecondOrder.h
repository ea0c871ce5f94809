#pragma once
// Quadratic (tet10) elements: one mid node per mesh edge, placed by the caller (on the exact
// CAD face or edge for boundary edges), kept straight wherever curving would fold a tet.
#include <cstdint>
#include <functional>
#include <vector>

#include "Geometry.h"
#include "domain/HierarchicalOracle.h"
#include "features/CurveRegistry.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

// Where the mid node of edge (a, b) goes; `straightMidpoint` = (points[a] + points[b]) / 2.
// Called once per edge, in the order the mid nodes are created, with a < b.
using MidNodePlacer = std::function<Point3(int64_t a, int64_t b, const Point3& straightMidpoint)>;

// Turns a first-order mesh into a second-order one:
//  - one mid node per unique edge, numbered after the existing points in the order the edges
//    are met going through tets in order and each tet's edges in the order 01,12,20,03,13,23;
//  - mesh.tet_mid_nodes filled in that edge order;
//  - vertex_dimension of a mid node: 1 on a feature edge, 2 on an edge of a boundary triangle
//    (mesh.boundary, or extractBoundary(mesh) when mesh.boundary is empty), 3 otherwise;
//    vertex_curve: the feature edge's curve id, else -1; vertex_boundary_entry: -1. These
//    arrays are only extended when the mesh has them (empty stays empty).
// Safety: the placed position is kept only if every tet that has the edge stays valid, i.e.
// its Jacobian determinant at the four corners, the centroid and C3D10's four integration
// points is > 0 and at least 0.2%
// of the straight-edged tet's (6 x volume), with the mid nodes placed so far. Otherwise the
// mid node goes back to the straight midpoint (also when the placer returns a non-finite
// point). Returns the number of such fall-backs.
// A mesh that is already second order is left unchanged (returns 0).
int makeSecondOrder(TetMesh& mesh, const MidNodePlacer& place);

// Whether tet t of a second-order mesh passes the safety rule above with its current nodes.
bool curvedTetIsValid(const TetMesh& mesh, size_t t);

// Second chance for the mid nodes of feature edges that makeSecondOrder left straight: where
// two curves leave a vertex tangentially, a quadratic edge whose mid node is at the middle of
// its arc leaves the vertex along the other curve, and the tets holding both edges have a zero
// Jacobian determinant at that vertex. A mid node on the curve but off-centre (towards the
// far end of the edge) tilts the quadratic edge back into the wedge. `onCurve(a, b, p)` puts
// p onto the curve of feature edge (a, b) (non-finite: no curve). Tries points at 45-30 % and
// 55-70 % of the edge, keeps the first that leaves every tet at the mid node valid; returns
// how many mid nodes it put onto their curve (the others stay straight).
int curveStraightFeatureMidNodes(TetMesh& mesh, const MidNodePlacer& onCurve);

// Second order on the exact geometry, for a mesh whose boundary nodes are on it (after the
// boundary snap; mesh.boundary current): the mid node of a feature edge goes onto its curve
// (`curves`), that of another boundary edge onto the boundary of the oracle entry both its ends
// lie on (`vertexEntry`, BoundarySnapResult::vertex_entry) or else the nearest boundary, the
// others stay straight; then curveStraightFeatureMidNodes. Returns the mid nodes left straight
// against their placement (makeSecondOrder's fall-backs less those curved afterwards).
int64_t makeSecondOrderOnGeometry(TetMesh& mesh, const HierarchicalOracle& oracle, const CurveRegistry& curves,
                                  const std::vector<int>& vertexEntry);

}  // namespace oraclemesh
