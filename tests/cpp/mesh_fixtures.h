#pragma once
// Small hand-made meshes for the tests of src/core/mesh/. Orientation is fixed here with an
// independent determinant so that a bug in mesh/Quality cannot hide itself.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "mesh/TetMesh.h"

namespace oraclemesh::test {

inline double orientation(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

// The unit cube [0,1]^3 (times `size`) split into the six Kuhn tets around the diagonal from
// corner 0 to corner 7; corner i is at (i & 1, (i >> 1) & 1, (i >> 2) & 1) * size. Tet k follows
// the axis order perms[k]: corners 0, e_a, e_a + e_b, 7, then two corners swapped if needed
// for positive orientation. With two_materials, tets where x comes before y (the half x >= y)
// get material 1 and the others material 2, so the interface is the plane x = y: the two
// triangles {0, 3, 7} and {0, 4, 7}.
inline TetMesh kuhnCube(bool two_materials = false, double size = 1.0) {
  TetMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.points.push_back({size * (i & 1), size * ((i >> 1) & 1), size * ((i >> 2) & 1)});
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {2, 0, 1}, {1, 0, 2}, {1, 2, 0}, {2, 1, 0}};
  for (const auto& p : perms) {
    std::array<int64_t, 4> tet{0, int64_t{1} << p[0], (int64_t{1} << p[0]) + (int64_t{1} << p[1]), 7};
    if (orientation(mesh.points[tet[0]], mesh.points[tet[1]], mesh.points[tet[2]], mesh.points[tet[3]]) < 0)
      std::swap(tet[1], tet[2]);
    mesh.tets.push_back(tet);
    const bool xBeforeY = std::find(p, p + 3, 0) < std::find(p, p + 3, 1);
    mesh.tet_materials.push_back(two_materials && !xBeforeY ? 2 : 1);
  }
  // Every cube corner is on the boundary; 0 and 7 are also where features would meet.
  mesh.vertex_dimension.assign(8, 2);
  mesh.vertex_curve.assign(8, -1);
  return mesh;
}

// One tet with corners 0, e_x, e_y, e_z (positive orientation), material 1.
inline TetMesh cornerTet() {
  TetMesh mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.tets = {{0, 1, 2, 3}};
  mesh.tet_materials = {1};
  return mesh;
}

}  // namespace oraclemesh::test
