#include "improve/SizeCriteria.h"

#include <algorithm>
#include <limits>

namespace oraclemesh {

double SizeCriteria::strictestFacetSize(const std::set<int>& materials, const Point3& p) const {
  if (!facet || materials.empty()) return 0;
  double strictest = std::numeric_limits<double>::infinity();
  for (int material : materials) strictest = std::min(strictest, facet(material, p));
  return strictest;
}

void SizeBound::include(const TetSize& s) {
  circumradius = std::max(circumradius, s.circumradius);
  radius_edge_ratio = std::max(radius_edge_ratio, s.radius_edge_ratio);
}

bool SizeBound::admits(int material, const Point3& a, const Point3& b, const Point3& c, const Point3& d) const {
  const TetSize s = tetSize(a, b, c, d);
  const bool radiusWithin = s.circumradius <= circumradius;
  const bool ratioWithin = s.radius_edge_ratio <= radius_edge_ratio;
  if (radiusWithin && ratioWithin) return true;
  if (!criteria) return false;
  if (!ratioWithin && !(criteria->cell_ratio && s.radius_edge_ratio <= criteria->cell_ratio(material))) return false;
  if (!radiusWithin) {
    // At the centroid: a point of the tet (a flattish tet's circumcentre can lie far outside).
    const double size = criteria->cell ? criteria->cell(material, 0.25 * (a + b + c + d)) : 0;
    if (!(size > 0 && s.circumradius <= size)) return false;
  }
  return true;
}

}  // namespace oraclemesh
