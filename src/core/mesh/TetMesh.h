#pragma once
// The mesher's result, independent of the engine that made it.
#include <array>
#include <cstdint>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

struct BoundaryTriangle {
  std::array<int64_t, 3> v{};  // oriented so the normal points from material_in to material_out
  int material_in = 0;         // material id on the side the normal points away from
  int material_out = 0;        // 0 = outside the domain
};

struct TetMesh {
  std::vector<Point3> points;
  // Corner vertices: (v1-v0)x(v2-v0).(v3-v0) > 0 (VTK / CGAL orientation).
  std::vector<std::array<int64_t, 4>> tets;
  std::vector<int> tet_materials;  // one per tet, > 0
  std::vector<BoundaryTriangle> boundary;  // faces between different materials or the outside
  std::vector<std::array<int64_t, 2>> feature_edges;
  std::vector<int> feature_edge_curves;  // curve id per feature edge
  // 0 corner of features, 1 on a feature curve, 2 on a boundary surface, 3 interior.
  std::vector<int> vertex_dimension;
  // Feature curve id of each dimension-1 vertex (-1 for all others); lets later phases put
  // such vertices back onto their exact B-rep edge.
  std::vector<int> vertex_curve;
  // Oracle entry on whose boundary a dimension-2 vertex lies exactly, as the engine that
  // placed it knows (an oracle crossing point or a projection onto that entry), else -1;
  // empty means unknown for every vertex. The boundary snap takes such vertices as on their
  // face instead of projecting them again. Whoever moves a point must reset its entry.
  std::vector<int> vertex_boundary_entry;

  // Second order (empty when element_order == 1): mid-edge nodes per tet in the order
  // 01, 12, 20, 03, 13, 23 (= FreeCAD's 12, 23, 31, 14, 24, 34), indices into `points`.
  std::vector<std::array<int64_t, 6>> tet_mid_nodes;

  int order() const { return tet_mid_nodes.empty() ? 1 : 2; }
};

}  // namespace oraclemesh
