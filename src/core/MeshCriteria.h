#pragma once
// Per-material refinement criteria (thesis §2.3.3, Rule Set R; same meaning as CGAL Mesh_3's criteria).
// Lengths are in model units (mm in FreeCAD).
#include <algorithm>
#include <map>

namespace oraclemesh {

// Which point of a cell decides its material: the circumcentre (Pons 2007, as CGAL Mesh_3
// does) or the barycentre (thesis §4.1). The job names it (JobSpec), the thesis engine uses it.
enum class MaterialAssignment { Circumcenter, Barycenter };

struct MaterialCriteria {
  double cell_size = 0;               // circumradius bound of tets
  double cell_radius_edge_ratio = 2;  // circumradius / shortest edge bound
  double facet_size = 0;              // surface Delaunay ball radius bound
  double facet_distance = 0;          // distance of facet circumcentre to the surface
  double facet_angle = 25;            // minimum facet angle, degrees (0 = off)
  double edge_size = 0;               // feature edge length bound (protecting balls)
};

struct CriteriaTable {
  MaterialCriteria defaults;
  std::map<int, MaterialCriteria> per_material;  // already merged with the defaults

  const MaterialCriteria& of(int material) const {
    auto it = per_material.find(material);
    return it == per_material.end() ? defaults : it->second;
  }

  // The strictest value of one criterion over all materials, for settings that take one value
  // for the whole mesh: the smallest when smaller is stricter (sizes), else the largest.
  double strictest(double MaterialCriteria::*field, bool smallerIsStricter = true) const {
    double value = defaults.*field;
    for (const auto& [material, c] : per_material)
      value = smallerIsStricter ? std::min(value, c.*field) : std::max(value, c.*field);
    return value;
  }
};

}  // namespace oraclemesh
