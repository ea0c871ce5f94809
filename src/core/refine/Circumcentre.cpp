#include "refine/Circumcentre.h"

#include <CGAL/Cartesian_converter.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace oraclemesh::refine {

namespace {

using Point = CGAL::Epick::Point_3;
using Exact = CGAL::Simple_cartesian<CGAL::Exact_rational>;

bool finite(const Point& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

// The double direction of an exact vector: scaled by its largest coordinate first, so that
// a vector beyond the range of doubles still has one.
bool directionOf(const Exact::Vector_3& v, std::array<double, 3>& direction) {
  Exact::FT largest = 0;
  for (int i = 0; i < 3; ++i) largest = std::max(largest, CGAL::abs(v[i]));
  if (largest == 0) return false;
  double length = 0;
  for (int i = 0; i < 3; ++i) {
    direction[i] = CGAL::to_double(v[i] / largest);
    length += direction[i] * direction[i];
  }
  length = std::sqrt(length);
  if (!(length > 0)) return false;
  for (double& x : direction) x /= length;
  return true;
}

}  // namespace

Point finiteCircumcentre(const Point& a, const Point& b, const Point& c, const Point& d, double farAway) {
  const Point rounded = CGAL::circumcenter(a, b, c, d);
  if (finite(rounded)) return rounded;
  const CGAL::Cartesian_converter<CGAL::Epick, Exact> exact;
  const std::array<Exact::Point_3, 4> corners{exact(a), exact(b), exact(c), exact(d)};
  std::array<double, 3> direction{0, 0, 0};
  bool known = false;
  if (CGAL::orientation(corners[0], corners[1], corners[2], corners[3]) != CGAL::COPLANAR) {
    const Exact::Point_3 centre = CGAL::circumcenter(corners[0], corners[1], corners[2], corners[3]);
    const Point inDoubles(CGAL::to_double(centre.x()), CGAL::to_double(centre.y()), CGAL::to_double(centre.z()));
    if (finite(inDoubles)) return inDoubles;
    known = directionOf(centre - corners[0], direction);
  } else {
    // No sphere: the axis of the flat cell's circle, taken through its largest face.
    Exact::Vector_3 normal = CGAL::NULL_VECTOR;
    Exact::FT largest = -1;
    for (int skip = 0; skip < 4; ++skip) {
      const Exact::Point_3 &p = corners[(skip + 1) & 3], &q = corners[(skip + 2) & 3], &r = corners[(skip + 3) & 3];
      const Exact::Vector_3 n = CGAL::cross_product(q - p, r - p);
      if (n.squared_length() > largest) largest = n.squared_length(), normal = n;
    }
    known = directionOf(normal, direction);
  }
  if (!known) return a;  // four equal corners: no cell a triangulation would hold
  return Point(a.x() + farAway * direction[0], a.y() + farAway * direction[1], a.z() + farAway * direction[2]);
}

}  // namespace oraclemesh::refine
