#pragma once
// Per-material refinement criteria (thesis §2.3.3, Rule Set R; same meaning as CGAL Mesh_3's criteria).
// Lengths are in model units (mm in FreeCAD).
#include <algorithm>
#include <limits>
#include <map>
#include <memory>

#include "sizing/BondedWedges.h"
#include "sizing/SizeField.h"

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
  // Which of the sizes above the job left unset, so that the sizing field (CriteriaTable::field)
  // lowers them where the geometry asks for it; a size the user gave is taken as it is.
  struct FromField {
    bool cell_size = false, facet_size = false, facet_distance = false, edge_size = false;
  } from_field;
};

// How the sizes the sizing field gives turn into the other criteria. The facet distance as
// resolveCriteria derives it from a facet size (job/ResolvedCriteria.cpp); edges at the size
// itself, not half of it as there: the field is already the local size (12 segments around a
// circle on its faces), and halving it again made the presse's feature curves twice as dense
// as its surfaces for nothing but time.
constexpr double kFacetDistancePerSize = 0.1;
constexpr double kEdgeSizePerSize = 1.0;
// Cells may be this much larger than the surface sizes of curvature and short edges ask for
// (not than a wall's thickness: a thin wall keeps its layers). Those sizes are surface
// Delaunay ball radii, 12 segments around a circle; tets of that circumradius filled the
// interior next to every curved face with far more tets per boundary triangle than Gmsh
// makes, for no gain in the boundary or the volume.
constexpr double kCellSizePerSurfaceSize = 2.0;

struct CriteriaTable {
  MaterialCriteria defaults;
  std::map<int, MaterialCriteria> per_material;  // already merged with the defaults
  // Sizes from the geometry (curvature, short edges, wall thickness); null when the job
  // leaves sizing to the constants alone.
  std::shared_ptr<const SizeField> field;
  // The cells' sizes from the same samples (kCellSizePerSurfaceSize); set whenever `field` is.
  std::shared_ptr<const SizeField> cell_field;
  // Sizes that keep gaps between parts open; null when there are none. They lower the sizes
  // on the surfaces (facets, facet distance, feature edges), the user's too: two parts apart
  // stay apart at every mesh size. Not the cells: a gap is empty space, the faces across it
  // are what must not meet, and the cells behind them grade by their radius-edge bound.
  std::shared_ptr<const SizeField> gap_field;
  // Parts closer than this touch (job/ContactTolerance). The thesis engine refines a facet
  // between two parts that bridges wider empty space or has a corner farther from one of
  // them (refine/FacetCriteria.h, contact ends). 0: not checked.
  double contact_tolerance = 0;
  // Wedges beside tangent contacts bonded by the sizing (sizing/BondedWedges.h); null: none.
  std::shared_ptr<const BondedWedges> bonded_wedges;

  // The widest empty space between two parts that counts as touching at p: the contact
  // tolerance, or a bonded wedge's width there.
  double bondedWidthAt(const Point3& p) const {
    return bonded_wedges ? std::max(contact_tolerance, bonded_wedges->widthAt(p)) : contact_tolerance;
  }

  // Whether sizes vary over space (either field is set).
  bool varies() const { return field || gap_field; }

  const MaterialCriteria& of(int material) const {
    auto it = per_material.find(material);
    return it == per_material.end() ? defaults : it->second;
  }

  // The two fields at one point (infinity where a field is not set): a facet's criteria for
  // both of its materials read them once instead of once per material and criterion.
  struct FieldValues {
    double field = std::numeric_limits<double>::infinity();
    double gap = std::numeric_limits<double>::infinity();
    // The cell field; only the thesis engine's corner bounds fill it (RuleSetTRefiner::fieldsBelow).
    double cell = std::numeric_limits<double>::infinity();
  };
  FieldValues fieldsAt(const Point3& p) const {
    FieldValues v;
    if (field) v.field = field->at(p);
    if (gap_field) v.gap = gap_field->at(p);
    return v;
  }

  // The criteria at p, a point of (or on the boundary of) `material`: the constants, lowered by
  // the sizing field where the job left them unset, and on the surfaces by the gap sizes.
  double cellSizeAt(int material, const Point3& p) const {
    const MaterialCriteria& c = of(material);
    return cell_field && c.from_field.cell_size ? std::min(c.cell_size, cell_field->at(p)) : c.cell_size;
  }
  double facetSizeAt(int material, const Point3& p) const { return facetSize(material, fieldsAt(p)); }
  double facetDistanceAt(int material, const Point3& p) const { return facetDistance(material, fieldsAt(p)); }
  double facetSize(int material, const FieldValues& at) const {
    const MaterialCriteria& c = of(material);
    const double size = c.from_field.facet_size ? std::min(c.facet_size, at.field) : c.facet_size;
    return std::min(size, at.gap);
  }
  double facetDistance(int material, const FieldValues& at) const {
    const MaterialCriteria& c = of(material);
    const double distance =
        c.from_field.facet_distance ? std::min(c.facet_distance, kFacetDistancePerSize * at.field) : c.facet_distance;
    return std::min(distance, kFacetDistancePerSize * at.gap);
  }
  // Feature edges belong to no one material: the strictest edge_size, lowered by the field
  // unless some material was given its edge size, and by the gaps.
  double edgeSizeAt(const Point3& p) const {
    double size = strictest(&MaterialCriteria::edge_size);
    if (field && edgeSizeFromField()) size = std::min(size, kEdgeSizePerSize * field->at(p));
    if (gap_field) size = std::min(size, kEdgeSizePerSize * gap_field->at(p));
    return size;
  }
  bool edgeSizeFromField() const {
    if (!defaults.from_field.edge_size) return false;
    for (const auto& [material, c] : per_material)
      if (!c.from_field.edge_size) return false;
    return true;
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
