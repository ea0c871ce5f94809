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

}  // namespace oraclemesh
