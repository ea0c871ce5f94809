#include "features/CurveRegistry.h"

#include <cmath>

#include "domain/BrepTopology.h"

namespace oraclemesh {

void CurveRegistry::addBrepEdge(int curve, int entry, int edge) {
  Origin origin;
  origin.entry = entry;
  origin.edge = edge;
  origins_[curve] = std::move(origin);
}

void CurveRegistry::addJunction(int curve, std::shared_ptr<const JunctionCurves> junctions, int junction) {
  Origin origin;
  origin.junction = junction;
  origin.junctions = std::move(junctions);
  origins_[curve] = std::move(origin);
}

void CurveRegistry::addUserPolyline(int curve, std::shared_ptr<const std::vector<Point3>> polyline,
                                    std::shared_ptr<const UserCurve> exact) {
  Origin origin;
  origin.user = std::move(polyline);
  origin.user_curve = std::move(exact);
  origins_[curve] = std::move(origin);
}

void CurveRegistry::addPolylines(const FeatureGraph& graph, const std::shared_ptr<const JunctionCurves>& junctions,
                                 const std::vector<std::shared_ptr<const std::vector<Point3>>>& userPolylines,
                                 const std::vector<std::shared_ptr<const UserCurve>>& userCurves) {
  for (const FeaturePolyline& pl : graph.polylines) {
    std::shared_ptr<const std::vector<Point3>> polyline;
    if (pl.user >= 0)
      polyline = userPolylines[pl.user];
    else if (isTriangleSurfaceEdge(pl))
      polyline = std::make_shared<const std::vector<Point3>>(pl.points);
    origins_[pl.curve] = {pl.source, pl.edge, pl.junction, pl.junction >= 0 ? junctions : nullptr, std::move(polyline),
                          pl.user >= 0 && pl.user < static_cast<int>(userCurves.size()) ? userCurves[pl.user] : nullptr};
  }
}

int CurveRegistry::entryOf(int curve) const {
  auto it = origins_.find(curve);
  return it == origins_.end() ? -1 : it->second.entry;
}

BoundaryProjection CurveRegistry::project(int curve, const Point3& p) const {
  auto it = origins_.find(curve);
  if (it == origins_.end()) return {};
  const Origin& origin = it->second;
  if (origin.junction >= 0 && origin.junctions) return origin.junctions->projectOnCurve(origin.junction, p);
  if (origin.user) {
    const Point3 q = origin.user_curve ? origin.user_curve->nearest(p) : nearestOnPolyline(*origin.user, p).point;
    return {q, -1, distance(p, q)};
  }
  if (origin.entry < 0 || origin.edge < 0) return {};
  const auto* solid = oracle_->entries()[origin.entry].source->brepTopology();
  if (!solid) return {};
  return solid->projectOnEdge(p, origin.edge);
}

Point3 CurveRegistry::ontoCurve(int curve, const Point3& p) const {
  const BoundaryProjection q = project(curve, p);
  return std::isfinite(q.distance) ? q.point : p;
}

}  // namespace oraclemesh
