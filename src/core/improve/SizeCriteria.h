#pragma once
// The job's size criteria as the improvement operations see them, and the bound every new tet
// of an operation must keep. Where an operation lengthens a feature edge or enlarges a boundary
// triangle or a tet, the result must be within these criteria or no larger than the largest
// there was. Without them the operations keep the largest there was, and no curve vertex is
// collapsed.
#include <functional>
#include <set>

#include "Geometry.h"
#include "improve/TetShape.h"

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
  // The radius-edge ratio bound of a material's tets.
  std::function<double(int)> cell_ratio;

  // The strictest facet size of `materials` at p; 0 without one.
  double strictestFacetSize(const std::set<int>& materials, const Point3& p) const;
};

// What a new tet may be: no bigger in circumradius and no worse in radius-edge ratio than the
// worst of the tets the operation replaces, or, for either measure it exceeds, within the
// job's criterion for the tet's material (the cell size at its centroid, the ratio bound),
// so that cells that met the engine's criteria still meet them. A criterion that is not given
// (or 0) admits nothing beyond the old tets.
struct SizeBound {
  double circumradius = 0;
  double radius_edge_ratio = 0;
  const SizeCriteria* criteria = nullptr;

  void include(const TetSize& s);
  bool admits(int material, const Point3& a, const Point3& b, const Point3& c, const Point3& d) const;
};

}  // namespace oraclemesh
