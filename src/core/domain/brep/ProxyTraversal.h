#pragma once
// Walks of the tessellation proxy's AABB tree by plain floating-point distances: the
// triangles near a point, and the nearest one. CGAL's own sphere and closest-point queries
// decide with exact predicates, which fall back to multi-precision arithmetic so often near
// the surface that they were a third of inside() and most of project(); a prefilter only
// needs never to prune a box it should keep, so its callers carry a relative margin.
#include <cstddef>
#include <limits>

#include "domain/brep/BrepSolidImpl.h"

namespace oraclemesh {

inline double squaredDistanceToBox(const KPoint& q, const CGAL::Bbox_3& box) {
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const double c = q[i];
    const double gap = c < box.min(i) ? box.min(i) - c : (c > box.max(i) ? c - box.max(i) : 0.0);
    sum += gap * gap;
  }
  return sum;
}

// A traversal of the proxy tree that hands `visit` each triangle whose node boxes come within
// sqrt(reachSquared) of q, until `visit` returns false.
template <class Visit>
struct TrianglesNear {
  KPoint q;
  double reachSquared;
  Visit visit;
  bool going = true;
  bool go_further() const { return going; }
  void intersection(int, const ProxyPrimitive& primitive) { going = visit(static_cast<size_t>(primitive.id())); }
  bool do_intersect(int, const CGAL::AABB_node<CGAL::AABB_traits<Kernel, ProxyPrimitive>>& node) const {
    return squaredDistanceToBox(q, node.bbox()) <= reachSquared;
  }
};

template <class Visit>
bool visitTrianglesNear(const ProxyTree& tree, const KPoint& q, double reach, Visit visit) {
  TrianglesNear<Visit> traversal{q, reach * reach * (1 + 1e-9), visit};
  tree.traversal(0, traversal);
  return traversal.going;
}

// The proxy triangle nearest to q among those within `reach` (a GMP conversion of NaN, in
// CGAL's query, raises SIGFPE; here a NaN distance is never the nearest).
template <class SquaredDistance>
struct NearestTriangle {
  KPoint q;
  double bestSquared;
  SquaredDistance squaredDistance;
  size_t best = std::numeric_limits<size_t>::max();
  bool go_further() const { return true; }
  void intersection(int, const ProxyPrimitive& primitive) {
    const size_t id = static_cast<size_t>(primitive.id());
    const double d2 = squaredDistance(id);
    if (d2 < bestSquared) {
      bestSquared = d2;
      best = id;
    }
  }
  bool do_intersect(int, const CGAL::AABB_node<CGAL::AABB_traits<Kernel, ProxyPrimitive>>& node) const {
    return squaredDistanceToBox(q, node.bbox()) < bestSquared;
  }
};

}  // namespace oraclemesh
