// Nearest boundary points: onto the faces (candidates from the proxy, answered by
// OpenCASCADE), onto one face and onto one edge.
#include "domain/brep/BrepSolidImpl.h"

#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Tool.hxx>
#include <Precision.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Extrema_ExtPElS.hxx>
#include <Extrema_POnSurf.hxx>
#include <Standard_Failure.hxx>
#include <gp_Cone.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>
#include <gp_Sphere.hxx>
#include <TopLoc_Location.hxx>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "Error.h"
#include "domain/OpenCascadeWork.h"
#include "domain/brep/OcctConversions.h"
#include "domain/brep/ProxyTraversal.h"

namespace oraclemesh {

std::optional<BrepSolid::Impl::SurfaceFoot> BrepSolid::Impl::analyticFoot(const gp_Pnt& p, int face) const {
  const AnalyticSurface& surface = analytic[face];
  const double tolerance = 1e-12 * diagonal;
  Extrema_ExtPElS extrema;
  switch (surface.kind) {
    case AnalyticSurface::Kind::Plane:
      extrema.Perform(p, gp_Pln(surface.frame), tolerance);
      break;
    case AnalyticSurface::Kind::Cylinder:
      extrema.Perform(p, gp_Cylinder(surface.frame, surface.radius), tolerance);
      break;
    case AnalyticSurface::Kind::Cone:
      extrema.Perform(p, gp_Cone(surface.frame, surface.semiAngle, surface.radius), tolerance);
      break;
    case AnalyticSurface::Kind::Sphere:
      extrema.Perform(p, gp_Sphere(surface.frame, surface.radius), tolerance);
      break;
    case AnalyticSurface::Kind::Torus:
      extrema.Perform(p, surface.torus, tolerance);
      break;
    case AnalyticSurface::Kind::None:
      return std::nullopt;
  }
  if (!extrema.IsDone() || extrema.NbExt() == 0) return std::nullopt;
  int best = 0;
  double bestSquared = std::numeric_limits<double>::infinity(), nextSquared = bestSquared;
  for (int i = 1; i <= extrema.NbExt(); ++i) {
    const double d2 = extrema.SquareDistance(i);
    if (d2 < bestSquared) {
      nextSquared = bestSquared;
      bestSquared = d2;
      best = i;
    } else {
      nextSquared = std::min(nextSquared, d2);
    }
  }
  SurfaceFoot foot;
  foot.point = extrema.Point(best).Value();
  extrema.Point(best).Parameter(foot.u, foot.v);
  foot.distance = std::sqrt(bestSquared);
  foot.nextDistance = std::sqrt(nextSquared);
  return foot;
}

BoundaryProjection BrepSolid::Impl::projectOnFace(const gp_Pnt& p, int face) const {
  BoundaryProjection best;
  // On an analytic face whose surface's nearest point lies in the face, that point is the
  // face's nearest: no trimmed-face search (DistShapeShape was a third of the refinement of
  // presse_asm, through the gap criterion's projections).
  if (const std::optional<SurfaceFoot> foot = analyticFoot(p, face)) {
    std::unique_ptr<FaceIntersectors> lease = leaseIntersectors();
    const bool inDomain = domainOf(*lease, face).Perform(gp_Pnt2d(foot->u, foot->v)) == TopAbs_IN;
    giveBack(std::move(lease));
    if (inDomain) {
      best.point = toPoint3(foot->point);
      best.distance = foot->distance;
      best.patch = face;
      return best;
    }
  }
  // DistShapeShape handles the trimmed face completely: the surface extremum when its
  // (u,v) classifies inside the face, else the nearest point of the bounding edges.
  BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(p).Vertex(), faces[face], Extrema_ExtFlag_MIN);
  if (!dist.IsDone() || dist.NbSolution() == 0) return best;
  best.point = toPoint3(dist.PointOnShape2(1));
  best.distance = dist.Value();
  best.patch = face;
  return best;
}

BoundaryProjection BrepSolid::project(const Point3& p) const {
  const Impl& m = *impl_;
  if (!isFinite(p)) return {};  // CGAL's exact comparisons would convert its NaN (SIGFPE)
  const OpenCascadeWork working(m.name);
  const gp_Pnt q = toGp(p);
  BoundaryProjection best;
  try {
    if (!m.proxyTree) {
      for (int f = 0; f < faceCount(); ++f) {
        const BoundaryProjection c = m.projectOnFace(q, f);
        if (c.distance < best.distance) best = c;
      }
      return best;
    }
    // The true boundary is within `h` of the proxy, so a face can hold the nearest point only
    // if its proxy triangles come within d0 + 2h, d0 being the distance to the proxy.
    const KPoint kq(p[0], p[1], p[2]);
    const double h = m.proxy.deflection;
    const double d0 = std::sqrt(CGAL::to_double(m.proxyTree->squared_distance(kq)));
    const double reach = d0 + 2 * h;
    std::map<int, double> faceProxyDistance;
    visitTrianglesNear(*m.proxyTree, kq, reach, [&](size_t id) {
      const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(kq, m.proxyTriangle(ProxyMesh::Face_index(id)))));
      if (!(d <= reach * (1 + 1e-9))) return true;
      auto [it, fresh] = faceProxyDistance.emplace(m.proxyFaceOfTriangle[id], d);
      if (!fresh) it->second = std::min(it->second, d);
      return true;
    });
    std::vector<std::pair<double, int>> candidates;
    for (const auto& [f, d] : faceProxyDistance) candidates.emplace_back(d, f);
    std::sort(candidates.begin(), candidates.end());
    for (const auto& [proxyDistance, f] : candidates) {
      if (proxyDistance - h > best.distance) break;  // cannot beat the best exact answer
      const BoundaryProjection c = m.projectOnFace(q, f);
      if (c.distance < best.distance) best = c;
    }
    // Faces without triangles are not in the tree: check them exactly.
    if (!m.proxy.usable)
      for (int f = 0; f < faceCount(); ++f)
        if (!faceProxyDistance.count(f)) {
          TopLoc_Location loc;
          if (!BRep_Tool::Triangulation(m.faces[f], loc).IsNull()) continue;
          const BoundaryProjection c = m.projectOnFace(q, f);
          if (c.distance < best.distance) best = c;
        }
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to project a point onto input '" + m.name + "' (" + failure.GetMessageString() +
                ")");
  }
  return best;
}

BoundaryProjection BrepSolid::projectOnPatch(const Point3& p, int face) const {
  const Impl& m = *impl_;
  if (face < 0 || face >= faceCount() || !isFinite(p)) return {};
  const OpenCascadeWork working(m.name);
  const gp_Pnt q = toGp(p);
  try {
    // The mesh improvement asks this for every step of a vertex on a curved face. A face's
    // ShapeAnalysis_Surface keeps what it learnt of the surface (closed form on elementary
    // surfaces, a grid of samples on others) and then finds the foot by a few Newton steps;
    // only the foot's parameters need the face's domain test. The general distance to the
    // trimmed face, the fallback, is hundreds of times slower.
    std::unique_ptr<Impl::FaceIntersectors> lease = m.leaseIntersectors();
    Handle(ShapeAnalysis_Surface)& projector = lease->projectorByFace[face];
    if (projector.IsNull()) projector = new ShapeAnalysis_Surface(m.faceSurface[face]);
    const gp_Pnt2d uv = projector->ValueOfUV(q, Precision::Confusion());
    const gp_Pnt foot = projector->Value(uv);
    const bool inside = m.domainOf(*lease, face).Perform(uv) == TopAbs_IN;
    m.giveBack(std::move(lease));
    if (inside) {
      BoundaryProjection result;
      result.point = toPoint3(foot);
      result.distance = foot.Distance(q);
      result.patch = face;
      return result;
    }
    return m.projectOnFace(q, face);
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to project a point onto a face of input '" + m.name + "' (" +
                failure.GetMessageString() + ")");
  }
}

BoundaryProjection BrepSolid::projectOnEdge(const Point3& p, int edgeIndex) const {
  const Impl& m = *impl_;
  if (!isFinite(p)) return {};
  const OpenCascadeWork working(m.name);
  BoundaryProjection result;
  try {
    BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(toGp(p)).Vertex(), m.edges.at(edgeIndex),
                                    Extrema_ExtFlag_MIN);
    if (!dist.IsDone() || dist.NbSolution() == 0) return result;
    result.point = toPoint3(dist.PointOnShape2(1));
    result.distance = dist.Value();
    const std::vector<int>& adjacent = m.edgeFaces[edgeIndex];
    result.patch = adjacent.empty() ? -1 : adjacent.front();
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to project a point onto an edge of input '" + m.name + "' (" +
                failure.GetMessageString() + ")");
  }
  return result;
}

}  // namespace oraclemesh
