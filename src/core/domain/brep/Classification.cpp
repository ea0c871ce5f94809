// Which points are inside: the tessellation proxy's answer where it is trusted (outside every
// face's band); in a band, the side of the one analytic face nearest to the point where that
// can be proven; else OpenCASCADE's classifiers, one pool per solid.
#include "domain/brep/BrepSolidImpl.h"

#include <Standard_Failure.hxx>
#include <gp_Cone.hxx>

#include <algorithm>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "Error.h"
#include "domain/OpenCascadeWork.h"
#include "domain/brep/OcctConversions.h"
#include "domain/brep/ProxyTraversal.h"

namespace oraclemesh {

// The proxy's side answer holds at q when q is outside every face's band: farther from that
// face's triangles than twice the face's deviation from the B-rep. Stops at the first
// triangle within its face's band.
bool BrepSolid::Impl::proxyTrusted(const KPoint& q) const {
  return visitTrianglesNear(*proxyTree, q, proxy.exactBand, [&](size_t id) {
    const double band = faceBand[proxyFaceOfTriangle[id]];
    if (squaredDistanceToBox(q, proxyTriangleBox[id]) > band * band * (1 + 1e-9)) return true;
    // Not "> band * band": a NaN distance must not end the traversal.
    return !(CGAL::to_double(CGAL::squared_distance(q, proxyTriangle(ProxyMesh::Face_index(id)))) <= band * band);
  });
}

// OpenCASCADE's classifier shoots a ray from the point and, for each query, looks for a point
// inside some face to aim it at by classifying trial parameters against the face's boundary
// polygons: on assemblies with narrow gaps most refinement queries fall in the proxy's bands,
// and that search was half of the refinement time. Near one analytic face the side follows
// from the nearest boundary point instead. Let q be the nearest point of the face's whole
// surface to p (closed form), inside the face's domain, and r = |p - q|. When every other
// face is farther than r from p (its proxy triangles farther than r plus the face's crossing
// band, which bounds how far the face may lie from its triangles), q is the nearest point of
// the solid's boundary, no boundary point lies in the open ball of radius r around p, and p
// is on the side of the face that p - q points to. Unsure (nullopt) otherwise, and within
// 100 times the classifier's tolerance of the surface, where OpenCASCADE's "on" decides.
std::optional<bool> BrepSolid::Impl::sideOfNearestAnalyticFace(const Point3& p) const {
  if (!proxy.usable || solids.size() != 1) return std::nullopt;
  const KPoint kp(p[0], p[1], p[2]);
  // inside() asks only within the bands; insideExact() anywhere: points farther than 1 % of
  // the diagonal from every triangle (and beyond the bands) are left to OpenCASCADE.
  const double searchReach = std::max(proxy.exactBand + 2 * maxCrossingBand, 1e-2 * diagonal);
  auto squaredDistance = [&](size_t id) {
    return CGAL::to_double(CGAL::squared_distance(kp, proxyTriangle(ProxyMesh::Face_index(id))));
  };
  NearestTriangle<decltype(squaredDistance)> nearest{kp, searchReach * searchReach, squaredDistance};
  proxyTree->traversal(0, nearest);
  if (nearest.best == std::numeric_limits<size_t>::max()) return std::nullopt;
  const int face = proxyFaceOfTriangle[nearest.best];
  const AnalyticSurface& surface = analytic[face];
  if (surface.kind == AnalyticSurface::Kind::None) return std::nullopt;

  const gp_Pnt gp = toGp(p);
  const std::optional<SurfaceFoot> foot = analyticFoot(gp, face);
  if (!foot) return std::nullopt;
  const double r = foot->distance;
  const double margin = 100 * classifyTolerance;
  // Near the surface OpenCASCADE's tolerance decides; two feet about as near (a point near an
  // axis or a centre) leave the nearest one in doubt.
  if (r <= margin || foot->nextDistance <= r + margin) return std::nullopt;
  const double u = foot->u, v = foot->v;
  gp_Pnt onSurface;
  gp_Vec du, dv;
  faceSurface[face]->D1(u, v, onSurface, du, dv);
  gp_Vec normal = du.Crossed(dv);
  if (normal.Magnitude() <= 1e-9 * du.Magnitude() * dv.Magnitude()) return std::nullopt;  // apex, pole
  if (faces[face].Orientation() == TopAbs_REVERSED) normal.Reverse();
  const gp_Vec away(onSurface, gp);
  // The face's surface at the parameters must be the foot (the same parametrisation).
  if (std::abs(away.Magnitude() - r) > margin) return std::nullopt;

  // Every other face farther than r: one traversal that stops at the first face that may come
  // nearer. A face whose triangles come near can still be proven far by its own analytic
  // surface (a lower bound on the distance to the face): next to an edge the neighbour's
  // triangles are always near.
  std::vector<std::pair<int, bool>> farBySurface;  // faces tried by their surface, and the answer
  const bool clear = visitTrianglesNear(*proxyTree, kp, r + maxCrossingBand, [&](size_t id) {
    const int other = proxyFaceOfTriangle[id];
    if (other == face) return true;
    const double reach = r + crossingBand[other];
    if (squaredDistanceToBox(kp, proxyTriangleBox[id]) > reach * reach * (1 + 1e-9)) return true;
    // A NaN distance counts as near: the proof then leaves the answer to OpenCASCADE.
    if (std::sqrt(squaredDistance(id)) > reach * (1 + 1e-9)) return true;
    for (const auto& [tried, far] : farBySurface)
      if (tried == other) return far;
    const bool far = surfaceFartherThan(gp, other, r + margin);
    farBySurface.emplace_back(other, far);
    return far;
  });
  if (!clear) return std::nullopt;

  std::unique_ptr<FaceIntersectors> lease = leaseIntersectors();
  const bool inDomain = domainOf(*lease, face).Perform(gp_Pnt2d(u, v)) == TopAbs_IN;
  giveBack(std::move(lease));
  if (!inDomain) return std::nullopt;
  return away.Dot(normal) < 0;
}

// Whether every point of the face's whole analytic surface is farther than `distance` from p.
// Its nearest point is a foot of a perpendicular (closed form), except at a cone's apex, which
// is no such foot and is counted on its own; a sphere's centre or a cylinder's axis (no single
// foot) and non-analytic faces are never proven far.
bool BrepSolid::Impl::surfaceFartherThan(const gp_Pnt& p, int face, double distance) const {
  const AnalyticSurface& surface = analytic[face];
  if (surface.kind == AnalyticSurface::Kind::None) return false;
  const std::optional<SurfaceFoot> foot = analyticFoot(p, face);
  if (!foot || !(foot->distance > distance)) return false;
  if (surface.kind == AnalyticSurface::Kind::Cone) {
    const gp_Pnt apex = gp_Cone(surface.frame, surface.semiAngle, surface.radius).Apex();
    if (!(p.Distance(apex) > distance)) return false;
  }
  return true;
}

bool BrepSolid::Impl::classifyExact(const Point3& p) const {
  if (const std::optional<bool> side = sideOfNearestAnalyticFace(p)) return *side;
  return classifyByOpenCascade(p);
}

bool BrepSolid::Impl::classifyByOpenCascade(const Point3& p) const {
  const gp_Pnt q = toGp(p);
  for (const auto& pool : solids) {
    if (!pool->box.contains(p, classifyTolerance)) continue;
    std::unique_ptr<BRepClass3d_SolidClassifier> classifier;
    {
      std::lock_guard<std::mutex> lock(pool->mutex);
      if (!pool->idle.empty()) {
        classifier = std::move(pool->idle.back());
        pool->idle.pop_back();
      }
    }
    if (!classifier) {
      classifier = std::make_unique<BRepClass3d_SolidClassifier>();
      classifier->Load(pool->solid);
    }
    classifier->Perform(q, classifyTolerance);
    const TopAbs_State state = classifier->State();
    {
      std::lock_guard<std::mutex> lock(pool->mutex);
      pool->idle.push_back(std::move(classifier));
    }
    if (state == TopAbs_IN || state == TopAbs_ON) return true;
  }
  return false;
}

namespace {

// An exact classification of input `name`, with OpenCASCADE's failures turned into an Error
// that names the input.
template <class Classify>
auto classifying(const std::string& name, Classify classify) -> decltype(classify()) {
  const OpenCascadeWork working(name);
  try {
    return classify();
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to classify a point against input '" + name + "' (" +
                failure.GetMessageString() + "): check the solid with Part > Check geometry");
  }
}

}  // namespace

bool BrepSolid::insideExact(const Point3& p) const {
  if (!impl_->box.contains(p, impl_->classifyTolerance)) return false;
  return classifying(impl_->name, [&] { return impl_->classifyExact(p); });
}

bool BrepSolid::insideByOpenCascade(const Point3& p) const {
  if (!impl_->box.contains(p, impl_->classifyTolerance)) return false;
  return classifying(impl_->name, [&] { return impl_->classifyByOpenCascade(p); });
}

std::optional<bool> BrepSolid::insideByNearestAnalyticFace(const Point3& p) const {
  return classifying(impl_->name, [&] { return impl_->sideOfNearestAnalyticFace(p); });
}

bool BrepSolid::inside(const Point3& p) const {
  if (!impl_->box.contains(p, impl_->classifyTolerance)) return false;
  if (impl_->proxySide) {
    const KPoint q(p[0], p[1], p[2]);
    // Farther from the tessellation than it can be from the B-rep: both sides agree.
    if (impl_->proxyTrusted(q)) return (*impl_->proxySide)(q) == CGAL::ON_BOUNDED_SIDE;
  }
  return insideExact(p);
}

}  // namespace oraclemesh
