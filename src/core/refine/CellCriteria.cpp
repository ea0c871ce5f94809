#include "refine/CellCriteria.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace oraclemesh::refine {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// The kernel's own constructions, as the refiner's triangulation uses them, so the measures
// round the same way there and here.
K::Point_3 kernelPoint(const Point3& p) { return K::Point_3(p[0], p[1], p[2]); }

}  // namespace

double shortestEdge(const std::array<Point3, 4>& corners) {
  double shortest = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      shortest = std::min(shortest, CGAL::squared_distance(kernelPoint(corners[a]), kernelPoint(corners[b])));
  return std::sqrt(shortest);
}

double flatness(const std::array<Point3, 4>& corners) {
  const double shortest = shortestEdge(corners);
  return 6 *
         std::abs(CGAL::volume(kernelPoint(corners[0]), kernelPoint(corners[1]), kernelPoint(corners[2]),
                               kernelPoint(corners[3]))) /
         (shortest * shortest * shortest);
}

CellShape measureCell(const std::array<Point3, 4>& corners, double circumradius) {
  return {circumradius, shortestEdge(corners), flatness(corners)};
}

CellVerdict CellCriteria::judge(const CellShape& shape) const {
  CellVerdict v;
  double worst = 0;
  if (size_.fails(shape)) {
    worst = size_.excess(shape);
    v.sizeFails = true;
    v.reason = "circumradius above cell_size";
  }
  if (flat_.fails(shape)) {
    worst = std::max(worst, FlatCellCriterion::kExcess);
    v.sizeFails = true;
    v.reason = "flat cell (four nearly coplanar corners)";
  }
  if (radiusEdge_.bound > 0) {
    const double ratio = radiusEdge_.excess(shape);
    if (ratio > 1 && ratio > worst) {
      worst = ratio;
      v.reason = "radius-edge ratio above cell_radius_edge_ratio";
    }
  }
  v.badness = worst > 1 ? worst : 0;
  return v;
}

}  // namespace oraclemesh::refine
