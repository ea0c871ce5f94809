#pragma once
// The job's size criteria as the improvement operations see them: where an operation lengthens
// a feature edge or enlarges a boundary triangle, the result must be within these (or no larger
// than the largest there was). Without them the operations keep the largest there was, and no
// curve vertex is collapsed.
#include <functional>
#include <set>

#include "Geometry.h"

namespace oraclemesh {

struct SizeCriteria {
  // Feature edge length bound at a point (the job's edge size: on a curved curve also its
  // segments per circle at the fineness).
  std::function<double(const Point3&)> edge;
  // Facet size (a bound of the circumradius) of a material at a point; applied to triangles of
  // planar patches only (a chord of a curved face also has a facet distance to keep).
  std::function<double(int, const Point3&)> facet;
  // Cell size (the circumradius bound of tets) of a material at a point.
  std::function<double(int, const Point3&)> cell;

  // The strictest facet size of `materials` at p; 0 without one.
  double strictestFacetSize(const std::set<int>& materials, const Point3& p) const;
};

}  // namespace oraclemesh
