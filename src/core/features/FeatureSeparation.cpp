#include "features/FeatureSeparation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "features/RuleSetQ.h"

namespace oraclemesh {
namespace {

// Mesh_3 shrinks intersecting balls of non-neighbouring vertices to distance / 2.1; a little
// more margin here leaves it nothing to shrink.
constexpr double kSeparationDivisor = 2.5;

using GridCell = std::array<long long, 3>;

GridCell cellOf(const Point3& p, double cellSize) {
  return {static_cast<long long>(std::floor(p[0] / cellSize)), static_cast<long long>(std::floor(p[1] / cellSize)),
          static_cast<long long>(std::floor(p[2] / cellSize))};
}

struct SegmentRef {
  int polyline;
  int segment;  // points[segment] .. points[segment + 1]
};

}  // namespace

double segmentDistance(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  // The minimum over the square of parameters is at an interior stationary point or on an
  // edge of the square, where it is a point-to-segment distance.
  double best = std::min({distanceToSegment(a, c, d), distanceToSegment(b, c, d), distanceToSegment(c, a, b),
                          distanceToSegment(d, a, b)});
  const Point3 u = b - a, v = d - c, w = a - c;
  const double uu = dot(u, u), uv = dot(u, v), vv = dot(v, v), uw = dot(u, w), vw = dot(v, w);
  const double denominator = uu * vv - uv * uv;
  if (denominator > 1e-12 * uu * vv) {
    const double s = (uv * vw - vv * uw) / denominator;
    const double t = (uu * vw - uv * uw) / denominator;
    if (s > 0 && s < 1 && t > 0 && t < 1) best = std::min(best, distance(a + s * u, c + t * v));
  }
  return best;
}

FeatureEdgeSizes localFeatureEdgeSizes(const FeatureGraph& graph, double maxSize, double minSize,
                                       double endTolerance) {
  const size_t n = graph.polylines.size();
  FeatureEdgeSizes result;
  result.smallest = maxSize;
  result.closest_separation = std::numeric_limits<double>::infinity();
  result.at_points.resize(n);
  for (size_t i = 0; i < n; ++i) result.at_points[i].assign(graph.polylines[i].points.size(), maxSize);
  if (n == 0 || !(maxSize > 0)) return result;

  // Neighbours: polylines sharing an end vertex.
  std::vector<std::set<int>> shared(n);
  for (const StarVertex& star : findStarVertices(graph, endTolerance))
    for (const StarVertex::Incident& e : star.incident)
      for (const StarVertex::Incident& f : star.incident)
        if (e.polyline != f.polyline) shared[e.polyline].insert(f.polyline);

  // Separations beyond `reach` leave the size at maxSize, so a grid of that cell size finds
  // every segment that matters in the neighbouring cells.
  const double reach = kSeparationDivisor * maxSize;
  std::map<GridCell, std::vector<SegmentRef>> grid;
  auto forCellsOf = [&](const Point3& a, const Point3& b, double margin, auto&& visit) {
    Point3 lo, hi;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(a[k], b[k]) - margin;
      hi[k] = std::max(a[k], b[k]) + margin;
    }
    const GridCell c0 = cellOf(lo, reach), c1 = cellOf(hi, reach);
    for (long long x = c0[0]; x <= c1[0]; ++x)
      for (long long y = c0[1]; y <= c1[1]; ++y)
        for (long long z = c0[2]; z <= c1[2]; ++z) visit(GridCell{x, y, z});
  };
  for (size_t i = 0; i < n; ++i) {
    const std::vector<Point3>& p = graph.polylines[i].points;
    for (size_t k = 0; k + 1 < p.size(); ++k)
      forCellsOf(p[k], p[k + 1], 0, [&](const GridCell& c) {
        grid[c].push_back({static_cast<int>(i), static_cast<int>(k)});
      });
  }

  for (size_t i = 0; i < n; ++i) {
    const std::vector<Point3>& p = graph.polylines[i].points;
    std::vector<double>& size = result.at_points[i];
    double length = 0;
    for (size_t k = 0; k + 1 < p.size(); ++k) length += distance(p[k], p[k + 1]);
    const double lengthBound = std::max(minSize, std::min(maxSize, length / 3));
    std::fill(size.begin(), size.end(), lengthBound);
    for (size_t k = 0; k + 1 < p.size(); ++k) {
      double separation = std::numeric_limits<double>::infinity();
      forCellsOf(p[k], p[k + 1], reach, [&](const GridCell& c) {
        auto it = grid.find(c);
        if (it == grid.end()) return;
        for (const SegmentRef& s : it->second) {
          if (s.polyline == static_cast<int>(i)) continue;
          const std::vector<Point3>& q = graph.polylines[s.polyline].points;
          const double d = segmentDistance(p[k], p[k + 1], q[s.segment], q[s.segment + 1]);
          if (!(d < separation)) continue;
          // Curves meeting at a vertex: Mesh_3 shrinks the few balls there that intersect
          // (bounding them here as well cost part.step's 2.5-degree corners five times the
          // balls).
          if (shared[i].count(s.polyline)) continue;
          separation = d;
        }
      });
      if (separation < result.closest_separation) {
        result.closest_separation = separation;
        result.closest_at = 0.5 * (p[k] + p[k + 1]);
      }
      const double bound = std::max(minSize, separation / kSeparationDivisor);
      size[k] = std::min(size[k], bound);
      size[k + 1] = std::min(size[k + 1], bound);
    }
    for (double s : size) {
      if (s < maxSize) ++result.bounded_points;
      result.smallest = std::min(result.smallest, s);
    }
  }
  return result;
}

double edgeSizeOnPolyline(const std::vector<Point3>& points, const std::vector<double>& sizes, const Point3& p) {
  if (points.size() < 2 || sizes.size() != points.size()) return sizes.empty() ? 0.0 : sizes.front();
  double best = std::numeric_limits<double>::infinity(), size = sizes.front();
  for (size_t k = 0; k + 1 < points.size(); ++k) {
    double t = 0;
    const double d = distanceToSegment(p, points[k], points[k + 1], &t);
    if (d < best) {
      best = d;
      size = (1 - t) * sizes[k] + t * sizes[k + 1];
    }
  }
  return size;
}

}  // namespace oraclemesh
