#pragma once
// The measures every improvement operation judges a tetrahedron by: its exact orientation,
// its smallest dihedral angle (the quality the stage raises) and its size (circumradius and
// radius-edge ratio, which SizeCriteria.h's SizeBound limits).
#include <array>
#include <cstdint>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

using TetCorners = std::array<int64_t, 4>;

// Sign of (b-a)x(c-a).(d-a), exact (CGAL's filtered predicate): +1, 0 or -1.
int exactOrientation(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

// Smallest of the six dihedral angles, degrees.
double smallestDihedral(const Point3& a, const Point3& b, const Point3& c, const Point3& d);
double smallestDihedral(const std::vector<Point3>& points, const TetCorners& t);

// Signed volume of tet t (mesh/Quality.h's tetVolume of its corners).
double tetVolume(const std::vector<Point3>& points, const TetCorners& t);

// Circumradius of a boundary triangle (what the facet size bounds); infinite when it is flat.
double triangleCircumradius(const Point3& a, const Point3& b, const Point3& c);

struct TetSize {
  double circumradius = 0;
  double radius_edge_ratio = 0;
};

TetSize tetSize(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

}  // namespace oraclemesh
