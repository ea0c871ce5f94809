// The planar side of the thesis engine's planar-face layer: see PlanarFacets.h.
// CGAL before OpenCASCADE (OCCT's Handle macro breaks CGAL).
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include "refine/PlanarFacets.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <gp_Pln.hxx>

#include <algorithm>
#include <set>

#include "domain/BrepTopology.h"
#include "domain/brep/OcctConversions.h"
#include "features/BrepSharpEdges.h"

namespace oraclemesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb>;
using Delaunay2 = CGAL::Delaunay_triangulation_2<K, Tds>;

// The faces' borders must be constrained segments: the sharp edges of the solid at the
// job's angle, as the features step extracts them (same function, same threshold).
std::set<int> sharpEdgesOf(const BrepTopology& solid, int entry, double sharpAngleDeg) {
  std::set<int> sharp;
  if (!(sharpAngleDeg > 0)) return sharp;
  // Only which edges are sharp matters here, not their sampling: one segment per edge.
  for (const FeaturePolyline& pl : extractSharpEdges(solid, entry, sharpAngleDeg, solid.bbox().diagonal()).polylines)
    sharp.insert(pl.edge);
  return sharp;
}

}  // namespace

std::vector<PlanarFace> findPlanarFaces(const HierarchicalOracle& oracle, double sharpAngleDeg,
                                        std::vector<SkippedPlanarFace>* skipped) {
  std::vector<PlanarFace> faces;
  for (size_t entry = 0; entry < oracle.entries().size(); ++entry) {
    const auto* solid = oracle.entries()[entry].source->brepTopology();
    if (!solid) continue;
    TopTools_IndexedMapOfShape edgeMap;
    TopExp::MapShapes(solid->shape(), TopAbs_EDGE, edgeMap);
    const std::set<int> sharp = sharpEdgesOf(*solid, static_cast<int>(entry), sharpAngleDeg);
    for (int f = 0; f < solid->faceCount(); ++f) {
      const TopoDS_Face& topoFace = solid->face(f);
      BRepAdaptor_Surface surface(topoFace, false);
      if (surface.GetType() != GeomAbs_Plane) continue;
      std::string reason;
      for (TopExp_Explorer ex(topoFace, TopAbs_EDGE); ex.More() && reason.empty(); ex.Next()) {
        const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
        if (BRep_Tool::Degenerated(e)) continue;
        const int edge = edgeMap.FindIndex(e) - 1;
        if (BRep_Tool::IsClosed(e, topoFace))
          reason = "edge " + std::to_string(edge) + " is a seam of the face";
        else if (!sharp.count(edge))
          reason = "edge " + std::to_string(edge) + " is not sharp at features.sharp_angle_deg = " +
                   std::to_string(sharpAngleDeg) + " (a smooth border is no constrained segment)";
      }
      if (!reason.empty()) {
        if (skipped) skipped->push_back({static_cast<int>(entry), f, reason});
        continue;
      }
      const gp_Pln plane = surface.Plane();
      PlanarFace pf;
      pf.entry = static_cast<int>(entry);
      pf.face = f;
      pf.origin = toPoint3(plane.Location().XYZ());
      pf.u = toPoint3(plane.XAxis().Direction().XYZ());
      pf.v = toPoint3(plane.YAxis().Direction().XYZ());
      pf.normal = toPoint3(plane.Axis().Direction().XYZ());
      Bnd_Box box;
      BRepBndLib::Add(topoFace, box, false);
      double x0, y0, z0, x1, y1, z1;
      box.Get(x0, y0, z0, x1, y1, z1);
      const double grow = 10 * oracle.tolerance();
      pf.box.add(Point3{x0 - grow, y0 - grow, z0 - grow});
      pf.box.add(Point3{x1 + grow, y1 + grow, z1 + grow});
      faces.push_back(pf);
    }
  }
  return faces;
}

bool onCompositeFace(const PlanarFace& face, const Point3& p, const HierarchicalOracle& oracle, Point3* exact) {
  if (!face.box.contains(p)) return false;
  // Long enough to step over the oracle's tolerance, short enough to meet no other face.
  const double probe = 1e-6 * oracle.diagonal();
  const Point3 onPlane = p - face.height(p) * face.normal;
  for (const CompositeCrossing& x : oracle.crossings(onPlane - probe * face.normal, onPlane + probe * face.normal)) {
    if (x.entry != face.entry || x.patch != face.face) continue;
    if (exact) *exact = x.point;
    return true;
  }
  return false;
}

std::vector<PlanarTriangle> restrictedPlanarTriangles(const PlanarFace& face, const std::vector<Point3>& points,
                                                      const HierarchicalOracle& oracle,
                                                      const std::function<bool(const std::array<int, 3>&)>& wanted) {
  std::vector<std::pair<K::Point_2, int>> planar;
  planar.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const auto xy = face.toPlane(points[i]);
    planar.emplace_back(K::Point_2(xy[0], xy[1]), static_cast<int>(i));
  }
  // One by one in the given order: with cocircular points (grids of seeds) the triangulation
  // depends on the order, which the caller keeps stable.
  Delaunay2 dt;
  Delaunay2::Face_handle hint;
  for (const auto& [point, index] : planar) {
    const size_t before = dt.number_of_vertices();
    const Delaunay2::Vertex_handle v = dt.insert(point, hint);
    if (dt.number_of_vertices() > before) v->info() = index;  // else a point repeated in the plane
    hint = v->face();
  }
  std::vector<PlanarTriangle> triangles;
  if (dt.dimension() < 2) return triangles;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    PlanarTriangle t;
    for (int k = 0; k < 3; ++k) t.corners[k] = f->vertex(k)->info();
    // Three points of one straight border (a subsegment split at its midpoint) are collinear
    // up to rounding, which may leave a needle of no width along the border: not a triangle.
    const K::Point_2 &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &c = f->vertex(2)->point();
    const double longest = std::sqrt(std::max({CGAL::squared_distance(a, b), CGAL::squared_distance(b, c),
                                               CGAL::squared_distance(c, a)}));
    if (std::abs(CGAL::area(a, b, c)) <= 0.5 * longest * oracle.tolerance()) continue;
    if (wanted && !wanted(t.corners)) continue;
    const Point3 centroid = (1.0 / 3) * (points[t.corners[0]] + points[t.corners[1]] + points[t.corners[2]]);
    if (!onCompositeFace(face, centroid, oracle)) continue;
    const K::Point_2 centre = CGAL::circumcenter(a, b, c);
    t.circumcentre = face.fromPlane(centre.x(), centre.y());
    t.radius = std::sqrt(CGAL::squared_distance(centre, a));
    triangles.push_back(t);
  }
  return triangles;
}

}  // namespace oraclemesh
