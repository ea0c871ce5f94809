#pragma once
// Shape measures of tetrahedra and the quality summary that goes into every job report.
// Angles are in degrees because that is how FEM engineers read them (and how the thesis
// states its bounds).
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "Geometry.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

// Corner pairs of the six tet edges in TetMesh's mid-node order 01, 12, 20, 03, 13, 23.
inline constexpr int kTetEdgeCorners[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

// Signed volume; positive when (b-a)x(c-a).(d-a) > 0, the VTK / CGAL orientation of TetMesh.
double tetVolume(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

// The six interior dihedral angles in degrees, at the edges in the order 01, 12, 20, 03, 13,
// 23. Unsigned: an inverted tet has the angles of its mirror image. A face of zero area
// makes the angles at its edges 0.
std::array<double, 6> dihedralAngles(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

// The circumcentre's offset from corner a; nullopt for a flat tet (no sphere) or one whose
// centre overflows.
std::optional<Point3> circumcentreFromA(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

// Circumradius over shortest edge: sqrt(6)/4 = 0.612 for the regular tet, unbounded for
// slivers' cousins (caps, needles). Infinity for a flat or degenerate tet.
double radiusEdgeRatio(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

// Nodes of a quadratic tet: the four corners, then the mid nodes of edges 01, 12, 20, 03, 13, 23.
using Tet10Nodes = std::array<Point3, 10>;

// Determinant of the Jacobian of the isoparametric map of a quadratic tet at the point with
// barycentric coordinates `barycentric` (relative to the corners). For straight edges (mid
// nodes at the edge midpoints) it is 6 x volume everywhere.
double tet10JacobianDeterminant(const Tet10Nodes& nodes, const std::array<double, 4>& barycentric);

// Smallest Jacobian determinant over the four corners, the centroid and the four integration
// points of CalculiX's C3D10: the corners are where a curved edge that folds the element shows
// up first, the integration points are where the solver evaluates it (it stops at a
// non-positive determinant there, "nonpositive jacobian"). <= 0: unusable for a solver.
double tet10MinJacobianAtCornersAndGaussPoints(const Tet10Nodes& nodes);

// Nodes of tet `t` of `mesh`; for a first-order mesh the mid nodes are the edge midpoints.
Tet10Nodes tet10Nodes(const TetMesh& mesh, size_t t);

// Volume of tet `t` as a solver integrates it: exact for tet10 (det J is a cubic polynomial,
// integrated exactly by a Gauss rule), the signed corner volume for tet4.
double elementVolume(const TetMesh& mesh, size_t t);

struct QualityReport {
  // Shape measures over all tets, from the corner vertices (the straight-sided shape: curved
  // boundary edges of a tet10 change its angles only slightly and have no standard angle).
  double min_dihedral = 0;  // degrees; 0 for an empty mesh
  double max_dihedral = 0;  // degrees
  double max_radius_edge = 0;
  double mean_radius_edge = 0;
  // Count of tets by their smallest dihedral angle, bin i = [10 i, 10 (i + 1)) degrees,
  // 18 bins (the last one also takes exactly 180).
  std::vector<int> min_dihedral_histogram = std::vector<int>(18, 0);
  std::map<int, int64_t> tets_per_material;
  // Volume as the solver sees it: exact curved volume for second order (elementVolume).
  std::map<int, double> volume_per_material;
  // Tets whose corner volume is <= 0 (checkConformity also counts folded tet10 elements).
  int64_t inverted = 0;
};

QualityReport measureQuality(const TetMesh& mesh);

}  // namespace oraclemesh
