#include "job/PoorElements.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "mesh/Quality.h"

namespace oraclemesh {

std::vector<int> curvesOfSmallAngle(const SmallInputAngle& angle, const FeatureGraph& features,
                                    const HierarchicalOracle& oracle) {
  std::vector<int> curves;
  if (angle.kind != "dihedral" && angle.kind != "contact") return curves;
  if (angle.curve >= 0) return {angle.curve};  // a triangle surface's sharp edge
  if (angle.edge < 0) return curves;
  for (const FeaturePolyline& pl : features.polylines)
    if (pl.edge == angle.edge && pl.source >= 0 && oracle.entries()[pl.source].source->name() == angle.input)
      curves.push_back(pl.curve);
  return curves;
}

namespace {

// Where each angle is: its point, or the polylines of its curves.
struct AngleSite {
  std::vector<Point3> points;
  std::vector<const FeaturePolyline*> polylines;
  Point3 low{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity()};
  Point3 high = -1.0 * low;

  void include(const Point3& p) {
    for (int k = 0; k < 3; ++k) low[k] = std::min(low[k], p[k]), high[k] = std::max(high[k], p[k]);
  }

  // A lower bound of distanceTo, to skip far sites cheaply.
  double boxDistance(const Point3& p) const {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double gap = std::max({low[k] - p[k], p[k] - high[k], 0.0});
      d2 += gap * gap;
    }
    return std::sqrt(d2);
  }

  double distanceTo(const Point3& p) const {
    double d = std::numeric_limits<double>::infinity();
    for (const Point3& q : points) d = std::min(d, distance(p, q));
    for (const FeaturePolyline* pl : polylines)
      for (size_t i = 0; i + 1 < pl->points.size(); ++i)
        d = std::min(d, distanceToSegment(p, pl->points[i], pl->points[i + 1]));
    return d;
  }
};

}  // namespace

PoorElements findPoorElements(const TetMesh& mesh, const std::vector<SmallInputAngle>& angles,
                              const FeatureGraph& features, const HierarchicalOracle& oracle,
                              const std::function<double(const Point3&)>& localEdgeSize) {
  std::vector<AngleSite> sites(angles.size());
  for (size_t i = 0; i < angles.size(); ++i) {
    const std::vector<int> curves = curvesOfSmallAngle(angles[i], features, oracle);
    if (curves.empty()) sites[i].points.push_back(angles[i].location);
    for (const FeaturePolyline& pl : features.polylines)
      if (std::find(curves.begin(), curves.end(), pl.curve) != curves.end()) sites[i].polylines.push_back(&pl);
    for (const Point3& p : sites[i].points) sites[i].include(p);
    for (const FeaturePolyline* pl : sites[i].polylines)
      for (const Point3& p : pl->points) sites[i].include(p);
  }
  std::vector<std::pair<double, int64_t>> poor;
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& c = mesh.tets[t];
    const auto a = dihedralAngles(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]], mesh.points[c[3]]);
    const double q = *std::min_element(a.begin(), a.end());
    if (q < kPoorElementDeg) poor.push_back({q, static_cast<int64_t>(t)});
  }
  std::sort(poor.begin(), poor.end());
  PoorElements out;
  for (const auto& [q, t] : poor) {
    out.under15++;
    if (q < 10) out.under10++;
    if (q < 5) out.under5++;
    const auto& c = mesh.tets[t];
    PoorElement e;
    e.tet = t;
    e.material = mesh.tet_materials[t];
    e.min_dihedral = q;
    double longest = 0;
    Point3 sum{0, 0, 0};
    for (int i = 0; i < 4; ++i) {
      sum = sum + mesh.points[c[i]];
      for (int j = i + 1; j < 4; ++j) longest = std::max(longest, distance(mesh.points[c[i]], mesh.points[c[j]]));
    }
    e.location = 0.25 * sum;
    const double reach = localEdgeSize ? std::max(longest, localEdgeSize(e.location)) : longest;
    double nearest = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < sites.size(); ++i) {
      double d = std::numeric_limits<double>::infinity();
      for (int64_t v : c)
        if (sites[i].boxDistance(mesh.points[v]) <= std::min(reach, d)) d = std::min(d, sites[i].distanceTo(mesh.points[v]));
      if (d <= reach && d < nearest) {
        nearest = d;
        e.small_angle = static_cast<int>(i);
        e.small_angle_distance = d;
      }
    }
    if (e.small_angle >= 0) out.near_small_angle++;
    if (out.listed.size() < kPoorElementsListed) out.listed.push_back(e);
  }
  return out;
}

}  // namespace oraclemesh
