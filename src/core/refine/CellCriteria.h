#pragma once
// The cell criteria of Rule Set T's T3 (thesis §3.3.1: circumradius greater than sigma, or
// radius-edge ratio greater than B), with one beyond the thesis (flat cells), as small
// objects on plain corner points: no triangulation is needed to test them.
#include <array>

#include "Geometry.h"
#include "MeshCriteria.h"

namespace oraclemesh::refine {

// What the cell criteria look at.
struct CellShape {
  double circumradius = 0;  // as the refiner computed it (a flat cell's may be its largest circle's)
  double shortestEdge = 0;
  double flatness = 0;      // 6 V / l_min^3: 0.71 for a regular tetrahedron, 0 for coplanar corners
};

// The corners in the triangulation's order (the volume's rounding depends on it).
double shortestEdge(const std::array<Point3, 4>& corners);
double flatness(const std::array<Point3, 4>& corners);
CellShape measureCell(const std::array<Point3, 4>& corners, double circumradius);

// Circumradius above cell_size (0 = off).
struct CellSizeCriterion {
  double bound = 0;
  bool fails(const CellShape& s) const { return bound > 0 && s.circumradius > bound; }
  double excess(const CellShape& s) const { return s.circumradius / bound; }
};

// Beyond the thesis: a cell whose four corners are (all but) coplanar, as boundary points
// placed symmetrically on two faces of a concave edge make them, has a fine radius-edge ratio
// but no volume, and no vertex move after refinement can open it. It counts as failing its
// size, so a point goes in like for any bad cell (with the same redirections).
struct FlatCellCriterion {
  static constexpr double kBound = 1e-4;   // flatness below which a cell is flat
  static constexpr double kExcess = 1e3;   // its badness: before any other bad cell
  static bool isFlat(double flatness) { return flatness < kBound; }
  bool fails(const CellShape& s) const { return isFlat(s.flatness); }
};

// Circumradius over shortest edge above cell_radius_edge_ratio (0 = off).
struct RadiusEdgeCriterion {
  double bound = 0;
  double excess(const CellShape& s) const { return s.circumradius / s.shortestEdge / bound; }
  bool fails(const CellShape& s) const { return bound > 0 && excess(s) > 1; }
};

struct CellVerdict {
  double badness = 0;         // how far beyond the worst failing criterion (> 1); 0 = good
  bool sizeFails = false;     // cell_size or the flat-cell criterion fails
  const char* reason = "";    // the criterion that set badness
};

// The cell criteria of one material.
class CellCriteria {
 public:
  // `cellSize`: the material's cell size where the cell is (CriteriaTable::cellSizeAt).
  CellCriteria(const MaterialCriteria& c, double cellSize) : size_{cellSize}, radiusEdge_{c.cell_radius_edge_ratio} {}
  explicit CellCriteria(const MaterialCriteria& c) : CellCriteria(c, c.cell_size) {}
  CellVerdict judge(const CellShape& shape) const;

 private:
  CellSizeCriterion size_;
  FlatCellCriterion flat_;
  RadiusEdgeCriterion radiusEdge_;
};

}  // namespace oraclemesh::refine
