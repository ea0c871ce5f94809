#include "improve/TetShape.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <limits>

#include "mesh/Quality.h"

namespace oraclemesh {

int exactOrientation(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto k = [](const Point3& p) { return K::Point_3(p[0], p[1], p[2]); };
  return static_cast<int>(CGAL::orientation(k(a), k(b), k(c), k(d)));
}

double smallestDihedral(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  const auto angles = dihedralAngles(a, b, c, d);
  return *std::min_element(angles.begin(), angles.end());
}

double smallestDihedral(const std::vector<Point3>& points, const TetCorners& t) {
  return smallestDihedral(points[t[0]], points[t[1]], points[t[2]], points[t[3]]);
}

TetSize tetSize(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  const Point3* p[4] = {&a, &b, &c, &d};
  double shortest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) shortest = std::min(shortest, distance(*p[i], *p[j]));
  const double ratio = radiusEdgeRatio(a, b, c, d);
  return {ratio * shortest, ratio};
}

void SizeBound::include(const TetSize& s) {
  circumradius = std::max(circumradius, s.circumradius);
  radius_edge_ratio = std::max(radius_edge_ratio, s.radius_edge_ratio);
}

}  // namespace oraclemesh
