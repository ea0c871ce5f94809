#include "improve/TetShape.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh/Quality.h"

namespace oraclemesh {

int exactOrientation(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto k = [](const Point3& p) { return K::Point_3(p[0], p[1], p[2]); };
  return static_cast<int>(CGAL::orientation(k(a), k(b), k(c), k(d)));
}

// The face normals' cosines find the smallest angle without six atan2 calls (the operations
// evaluate it millions of times: they were most of the stage's time). Near 0 degrees the
// cosine cannot rank angles, so there atan2 decides among the candidates, as accurate as
// dihedralAngles.
double smallestDihedral(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  constexpr double kRankableCosine = 0.99;  // below about 8 degrees the cosines tie
  const Point3 n[4] = {cross(d - b, c - b), cross(c - a, d - a), cross(d - a, b - a), cross(b - a, c - a)};
  double length[4];
  for (int k = 0; k < 4; ++k) length[k] = norm(n[k]);
  // The dihedral angle at the edge shared by faces k and l is 180 degrees minus the angle
  // between their outward normals.
  auto exact = [&](int k, int l) {
    return std::atan2(norm(cross(n[k], n[l])), -dot(n[k], n[l])) * (180.0 / M_PI);
  };
  int bestK = 0, bestL = 1;
  double bestCos = -2, smallest = 180;
  for (int k = 0; k < 4; ++k)
    for (int l = k + 1; l < 4; ++l) {
      const double denominator = length[k] * length[l];
      if (!(denominator > 0)) return 0;  // a face of zero area
      const double cosine = -dot(n[k], n[l]) / denominator;
      if (cosine > kRankableCosine) smallest = std::min(smallest, exact(k, l));
      if (cosine > bestCos) {
        bestCos = cosine;
        bestK = k;
        bestL = l;
      }
    }
  return bestCos > kRankableCosine ? smallest : exact(bestK, bestL);
}

double tetVolume(const std::vector<Point3>& points, const TetCorners& t) {
  return tetVolume(points[t[0]], points[t[1]], points[t[2]], points[t[3]]);
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

double triangleCircumradius(const Point3& a, const Point3& b, const Point3& c) {
  const double area2 = norm(cross(b - a, c - a));
  return area2 > 0 ? distance(a, b) * distance(b, c) * distance(c, a) / (2 * area2)
                   : std::numeric_limits<double>::infinity();
}

}  // namespace oraclemesh
