#include "improve/Smoothing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace oraclemesh {
namespace {

constexpr int kAscentSteps = 5;   // line searches per call
constexpr int kStepHalvings = 8;  // how far each line search backs off

struct Star {
  ImprovementMesh& mesh;
  int64_t v;
  std::vector<int64_t> tets;

  // Smallest dihedral angle over the star with v at q; -1 if a tet is not positive.
  double worstAt(const Point3& q, const SizeBound* bound) const {
    auto& p = mesh.points();
    const Point3 keep = p[v];
    p[v] = q;
    double worst = std::numeric_limits<double>::infinity();
    for (int64_t t : tets) {
      const TetCorners& c = mesh.tet(t);
      if (exactOrientation(p[c[0]], p[c[1]], p[c[2]], p[c[3]]) <= 0 ||
          (bound && !bound->admits(tetSize(p[c[0]], p[c[1]], p[c[2]], p[c[3]])))) {
        worst = -1;
        break;
      }
      worst = std::min(worst, smallestDihedral(p, c));
    }
    p[v] = keep;
    return worst;
  }

  // Smallest dihedral angle over the star, without the checks (for finite differences).
  double softWorstAt(const Point3& q) const {
    auto& p = mesh.points();
    const Point3 keep = p[v];
    p[v] = q;
    double worst = std::numeric_limits<double>::infinity();
    for (int64_t t : tets) worst = std::min(worst, smallestDihedral(p, mesh.tet(t)));
    p[v] = keep;
    return worst;
  }
};

double triangleCircumradius(const Point3& a, const Point3& b, const Point3& c) {
  const double area2 = norm(cross(b - a, c - a));
  return area2 > 0 ? distance(a, b) * distance(b, c) * distance(c, a) / (2 * area2)
                   : std::numeric_limits<double>::infinity();
}

// The largest boundary triangle circumradius (Planar) or feature edge length (Linear) at v
// with v at q: a move may not make it larger than it was (the facet and edge sizes still hold).
double boundarySizeAt(const ImprovementMesh& mesh, int64_t v, const Point3& q) {
  const VertexMobility& m = mesh.mobility(v);
  const auto& p = mesh.points();
  auto at = [&](int64_t w) -> const Point3& { return w == v ? q : p[w]; };
  double size = 0;
  for (const auto& t : m.boundary_triangles) size = std::max(size, triangleCircumradius(at(t[0]), at(t[1]), at(t[2])));
  if (m.freedom == VertexFreedom::Linear)
    for (int64_t w : m.feature_neighbours) size = std::max(size, distance(q, p[w]));
  return size;
}

Point3 project(const Point3& d, const VertexMobility& m) {
  switch (m.freedom) {
    case VertexFreedom::Free: return d;
    case VertexFreedom::Planar: return d - dot(d, m.axis) * m.axis;
    case VertexFreedom::Linear: return dot(d, m.axis) * m.axis;
    default: return {0, 0, 0};
  }
}

}  // namespace

bool smoothVertex(ImprovementMesh& mesh, int64_t v) {
  const VertexMobility& mobility = mesh.mobility(v);
  if (mobility.freedom == VertexFreedom::Fixed) return false;
  Star star{mesh, v, mesh.tetsOf(v)};
  if (star.tets.empty()) return false;
  auto& p = mesh.points();
  SizeBound bound;
  double shortest = std::numeric_limits<double>::infinity();
  for (int64_t t : star.tets) {
    const TetCorners& c = mesh.tet(t);
    bound.include(tetSize(p[c[0]], p[c[1]], p[c[2]], p[c[3]]));
    for (int64_t w : c)
      if (w != v) shortest = std::min(shortest, distance(p[v], p[w]));
  }
  const Point3 start = p[v];
  const double boundarySize = boundarySizeAt(mesh, v, start);
  double current = star.worstAt(start, &bound);
  if (current < 0) return false;
  Point3 position = start;
  const double h = 1e-7 * shortest;
  // Moves along `direction` by a fifth of the shortest edge, backing off until the worst angle
  // rises; false when no step along it does.
  auto lineSearch = [&](const Point3& direction) {
    const double length = norm(direction);
    if (!(length > 0)) return false;
    double stepLength = 0.2 * shortest;
    for (int k = 0; k < kStepHalvings; ++k, stepLength *= 0.5) {
      const Point3 q = position + (stepLength / length) * direction;
      const double worst = star.worstAt(q, &bound);
      if (worst > current && boundarySizeAt(mesh, v, q) <= boundarySize) {
        position = q;
        current = worst;
        return true;
      }
    }
    return false;
  };
  for (int step = 0; step < kAscentSteps; ++step) {
    // Ascent direction of the worst angle by central differences along the free axes.
    Point3 gradient{0, 0, 0};
    for (int axis = 0; axis < 3; ++axis) {
      Point3 dp = position, dm = position;
      dp[axis] += h;
      dm[axis] -= h;
      gradient[axis] = (star.softWorstAt(dp) - star.softWorstAt(dm)) / (2 * h);
    }
    if (lineSearch(project(gradient, mobility))) continue;
    // Where two worst angles meet, the gradient of one lowers the other: a compass search
    // along the free axes finds the way out.
    bool moved = false;
    for (int axis = 0; axis < 3 && !moved; ++axis)
      for (double sign : {1.0, -1.0}) {
        Point3 d{0, 0, 0};
        d[axis] = sign;
        if ((moved = lineSearch(project(d, mobility)))) break;
      }
    if (!moved) break;
  }
  if (position == start) return false;
  p[v] = position;
  mesh.markMoved(v);
  return true;
}

}  // namespace oraclemesh
