#pragma once
// Dihedral-angle measures of the sliver rule and of rule P (beyond the thesis), on plain
// points. Both measure many candidate cells and only compare the results, so the cheap forms
// come first and Quality's six exact angles last.
#include <algorithm>
#include <array>
#include <cmath>

#include "Geometry.h"
#include "mesh/Quality.h"

namespace oraclemesh::refine {

// The cosine of a tetrahedron's smallest dihedral angle (1 for a flat one), without trig.
inline double largestDihedralCosine(const std::array<Point3, 4>& p) {
  static constexpr int kFaceOpposite[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::array<Point3, 4> normal;
  std::array<double, 4> length;
  for (int k = 0; k < 4; ++k) {
    const auto& f = kFaceOpposite[k];
    normal[k] = cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]);
    length[k] = norm(normal[k]);
    if (!(length[k] > 0)) return 1;
  }
  double largestCosine = -1;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      largestCosine = std::max(largestCosine, -dot(normal[i], normal[j]) / (length[i] * length[j]));
  return largestCosine;
}

// The smallest dihedral angle of a tetrahedron in degrees, from the largest cosine between
// face normals: one acos instead of the six atan2 of Quality's dihedralAngles, since rule P
// measures tens of thousands of candidate cells and only compares the results.
inline double smallestDihedralDeg(const std::array<Point3, 4>& p) {
  return std::acos(std::clamp(largestDihedralCosine(p), -1.0, 1.0)) * 180 / M_PI;
}

// The smallest of Quality's six dihedral angles (what the mesh report measures).
inline double minDihedralDeg(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  const std::array<double, 6> angles = dihedralAngles(a, b, c, d);
  return *std::min_element(angles.begin(), angles.end());
}

}  // namespace oraclemesh::refine
