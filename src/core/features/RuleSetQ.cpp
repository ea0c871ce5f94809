#include "features/RuleSetQ.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace oraclemesh {

namespace {

// Polyline ends are exact B-rep vertices or clip points computed once and copied, so equal
// ends agree to rounding; a grid of cell size `tolerance` finds them without an O(n^2) scan.
using GridCell = std::array<long long, 3>;

GridCell cellOf(const Point3& p, double tolerance) {
  return {static_cast<long long>(std::floor(p[0] / tolerance)), static_cast<long long>(std::floor(p[1] / tolerance)),
          static_cast<long long>(std::floor(p[2] / tolerance))};
}

double endSegmentLength(const FeaturePolyline& polyline, bool atStart) {
  const std::vector<Point3>& p = polyline.points;
  return atStart ? distance(p[0], p[1]) : distance(p[p.size() - 1], p[p.size() - 2]);
}

}  // namespace

std::vector<StarVertex> findStarVertices(const FeatureGraph& graph, double tolerance) {
  std::vector<StarVertex> vertices;
  std::map<GridCell, std::vector<int>> grid;  // cell -> indices into `vertices`
  auto vertexAt = [&](const Point3& p) -> StarVertex& {
    const GridCell c = cellOf(p, tolerance);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (int v : it->second)
            if (distance(vertices[v].point, p) <= tolerance) return vertices[v];
        }
    grid[c].push_back(static_cast<int>(vertices.size()));
    vertices.push_back(StarVertex{p, {}, 0});
    return vertices.back();
  };
  for (size_t i = 0; i < graph.polylines.size(); ++i) {
    const FeaturePolyline& pl = graph.polylines[i];
    if (pl.points.size() < 2) continue;
    vertexAt(pl.points.front()).incident.push_back({static_cast<int>(i), true});
    vertexAt(pl.points.back()).incident.push_back({static_cast<int>(i), false});
  }
  std::vector<StarVertex> stars;
  for (StarVertex& v : vertices) {
    if (v.incident.size() < 2) continue;
    v.shortest_incident_length = std::numeric_limits<double>::infinity();
    for (const StarVertex::Incident& e : v.incident)
      v.shortest_incident_length =
          std::min(v.shortest_incident_length, endSegmentLength(graph.polylines[e.polyline], e.at_start));
    stars.push_back(std::move(v));
  }
  std::sort(stars.begin(), stars.end(), [](const StarVertex& a, const StarVertex& b) { return a.point < b.point; });
  return stars;
}

FeatureGraph equalizeStarSegments(const FeatureGraph& graph, const std::vector<StarVertex>& stars) {
  // Where each polyline end is a star vertex: the distance from the end to its new point.
  std::vector<double> startCut(graph.polylines.size(), 0), endCut(graph.polylines.size(), 0);
  std::map<Point3, int> starAt;  // star vertices by their (bitwise) end points
  for (size_t k = 0; k < stars.size(); ++k)
    for (const StarVertex::Incident& e : stars[k].incident) {
      const FeaturePolyline& pl = graph.polylines[e.polyline];
      starAt[e.at_start ? pl.points.front() : pl.points.back()] = static_cast<int>(k);
    }
  for (const StarVertex& star : stars) {
    // Free (thesis fig. 3.3): equal incident lengths and no incident segment reaching another
    // star vertex. Lengths compare to rounding, as a previous equalisation leaves them.
    bool free = true;
    for (const StarVertex::Incident& e : star.incident) {
      const FeaturePolyline& pl = graph.polylines[e.polyline];
      const Point3& neighbour = e.at_start ? pl.points[1] : pl.points[pl.points.size() - 2];
      free = free && endSegmentLength(pl, e.at_start) <= star.shortest_incident_length * (1 + 1e-9) &&
             !starAt.count(neighbour);
    }
    if (free || !(star.shortest_incident_length > 0)) continue;
    for (const StarVertex::Incident& e : star.incident)
      (e.at_start ? startCut : endCut)[e.polyline] = star.shortest_incident_length / 3;
  }
  FeatureGraph result = graph;
  for (size_t i = 0; i < graph.polylines.size(); ++i) {
    std::vector<Point3>& p = result.polylines[i].points;
    if (p.size() < 2 || (startCut[i] == 0 && endCut[i] == 0)) continue;
    // Both cuts are taken on the original end segments; on a one-segment polyline they are at
    // most a third of it from each end, so they stay in order.
    const Point3 first = p[0], second = p[1], last = p[p.size() - 1], beforeLast = p[p.size() - 2];
    if (endCut[i] > 0) {
      const Point3 back = last + (endCut[i] / distance(last, beforeLast)) * (beforeLast - last);
      p.insert(p.end() - 1, back);
    }
    if (startCut[i] > 0) {
      const Point3 front = first + (startCut[i] / distance(first, second)) * (second - first);
      p.insert(p.begin() + 1, front);
    }
  }
  return result;
}

}  // namespace oraclemesh
