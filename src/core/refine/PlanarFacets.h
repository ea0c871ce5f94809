#pragma once
// Planar B-rep faces kept flat by the thesis engine (thesis §4.1, "planar input polygons",
// left unfinished there): for a planar face G in its plane H, the mesh points lying on H are
// triangulated in 2D (Delaunay, in an orthonormal frame of H), the triangles are restricted
// to G's part of the composite boundary, and the engine inserts the circumcentres of those
// its 3D Delaunay triangulation lacks until every one is a 3D facet. This file holds the
// planar side (frames, the 2D triangulation, the restriction); no 3D triangulation type
// appears here, ThesisEngine.cpp asks which triangles are 3D facets.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "Geometry.h"
#include "domain/HierarchicalOracle.h"

namespace oraclemesh {

// A planar face of a B-rep entry of the oracle, with an orthonormal frame of its plane.
struct PlanarFace {
  int entry = -1;  // oracle entry
  int face = -1;   // B-rep face index, the boundary patch id of the entry's crossings
  Point3 origin{}, u{}, v{}, normal{};
  Bbox box;  // of the face, grown by ten times the oracle's tolerance

  double height(const Point3& p) const { return dot(p - origin, normal); }
  std::array<double, 2> toPlane(const Point3& p) const { return {dot(p - origin, u), dot(p - origin, v)}; }
  Point3 fromPlane(double x, double y) const { return origin + x * u + y * v; }
};

// A planar face of a B-rep input whose triangles are not recovered, and why.
struct SkippedPlanarFace {
  int entry = -1;
  int face = -1;
  std::string reason;
};

// The planar faces of the oracle's B-rep entries whose borders are all sharp edges at
// `sharpAngleDeg` (the edges the features step makes constrained segments of): only then do
// the constrained subsegments bound the face in the 2D triangulation, and only then is the
// recovery well posed. Planar faces with a smooth (tangent) or seam border go to `skipped`.
// Whether a face shows on the composite boundary is not decided here: faces buried inside
// higher-priority inputs simply get no restricted triangles.
std::vector<PlanarFace> findPlanarFaces(const HierarchicalOracle& oracle, double sharpAngleDeg,
                                        std::vector<SkippedPlanarFace>* skipped);

// Whether p (a point on or near the face's plane) lies on the composite boundary where that
// boundary is this face: a short probe across the plane at p crosses the composite boundary
// on this entry's face (the oracle picks one entry for coincident faces of several inputs,
// so a contact face is recovered once). `exact` receives the oracle's crossing point.
bool onCompositeFace(const PlanarFace& face, const Point3& p, const HierarchicalOracle& oracle,
                     Point3* exact = nullptr);

// A triangle of the 2D Delaunay triangulation of a face's points.
struct PlanarTriangle {
  std::array<int, 3> corners{};  // indices into the points given
  Point3 circumcentre{};         // on the plane
  double radius = 0;             // circumradius
};

// The 2D Delaunay triangulation of `points` (all on the face's plane) within that plane,
// restricted to the face: the triangles whose centroid is on the face's part of the composite
// boundary (onCompositeFace). Constrained subsegments along the face's borders that no point
// encroaches are Delaunay edges in the plane too, so each triangle lies wholly inside or
// wholly outside the face. `wanted` (corners -> bool) is asked first so that the engine pays
// the oracle only for the triangles it lacks; null = all triangles. Points that coincide in
// the plane keep the first one's index.
std::vector<PlanarTriangle> restrictedPlanarTriangles(const PlanarFace& face, const std::vector<Point3>& points,
                                                      const HierarchicalOracle& oracle,
                                                      const std::function<bool(const std::array<int, 3>&)>& wanted);

}  // namespace oraclemesh
