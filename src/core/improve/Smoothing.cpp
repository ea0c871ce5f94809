#include "improve/Smoothing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "mesh/Quality.h"

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
          (bound && !bound->admits(mesh.material(t), p[c[0]], p[c[1]], p[c[2]], p[c[3]]))) {
        worst = -1;
        break;
      }
      worst = std::min(worst, smallestDihedral(p, c));
    }
    p[v] = keep;
    return worst;
  }

  // Signed volume change per material of the star's tets with v moved from `from` to `to`.
  std::map<int, double> volumeChange(const Point3& from, const Point3& to) const {
    auto& p = mesh.points();
    const Point3 keep = p[v];
    std::map<int, double> change;
    for (const Point3* at : {&from, &to}) {
      p[v] = *at;
      const double sign = at == &from ? -1.0 : 1.0;
      for (int64_t t : tets) {
        const TetCorners& c = mesh.tet(t);
        change[mesh.material(t)] += sign * tetVolume(p[c[0]], p[c[1]], p[c[2]], p[c[3]]);
      }
    }
    p[v] = keep;
    return change;
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

// The largest boundary triangle circumradius or feature edge length at v with v at q.
double boundarySizeAt(const ImprovementMesh& mesh, int64_t v, const Point3& q) {
  const VertexMobility& m = mesh.mobility(v);
  const auto& p = mesh.points();
  auto at = [&](int64_t w) -> const Point3& { return w == v ? q : p[w]; };
  double size = 0;
  for (const auto& t : m.boundary_triangles) size = std::max(size, triangleCircumradius(at(t[0]), at(t[1]), at(t[2])));
  for (int64_t w : m.feature_neighbours)
    if (w >= 0) size = std::max(size, distance(q, p[w]));
  return size;
}

// Whether v at q keeps the facet and edge sizes: every boundary triangle and feature edge at v
// no larger than `largest` (boundarySizeAt where v was), or a feature edge within the job's edge
// size and a triangle of a planar patch within its facet size (SizeCriteria). Without the job's
// sizes a curve vertex whose feature edges are the longest at it could not move along its curve
// at all: any move lengthens one of them.
bool boundarySizesHold(const ImprovementMesh& mesh, int64_t v, const Point3& q, double largest,
                       const SizeCriteria& sizes, const std::set<int>& materials) {
  const VertexMobility& m = mesh.mobility(v);
  const auto& p = mesh.points();
  auto at = [&](int64_t w) -> const Point3& { return w == v ? q : p[w]; };
  for (int64_t w : m.feature_neighbours) {
    if (w < 0) continue;
    const double length = distance(q, p[w]);
    if (length > largest && !(sizes.edge && length <= sizes.edge(0.5 * (q + p[w])))) return false;
  }
  for (const auto& t : m.boundary_triangles) {
    const double radius = triangleCircumradius(at(t[0]), at(t[1]), at(t[2]));
    if (radius <= largest) continue;
    if (m.freedom != VertexFreedom::Planar) return false;
    if (!(radius <= sizes.strictestFacetSize(materials, (1.0 / 3) * (at(t[0]) + at(t[1]) + at(t[2]))))) return false;
  }
  return true;
}

// The unit normal of the boundary triangles at v with v at q (area-weighted, turned to `axis`).
Point3 surfaceNormalAt(const ImprovementMesh& mesh, int64_t v, const Point3& q) {
  const VertexMobility& m = mesh.mobility(v);
  const auto& p = mesh.points();
  auto at = [&](int64_t w) -> const Point3& { return w == v ? q : p[w]; };
  Point3 sum{0, 0, 0};
  for (const auto& t : m.boundary_triangles) {
    const Point3 n = cross(at(t[1]) - at(t[0]), at(t[2]) - at(t[0]));
    sum = sum + (dot(n, m.axis) < 0 ? -1.0 : 1.0) * n;
  }
  const double length = norm(sum);
  return length > 0 ? (1.0 / length) * sum : m.axis;
}

// The part of direction d along which v may move from q.
Point3 allowedDirection(const ImprovementMesh& mesh, int64_t v, const Point3& q, const Point3& d) {
  const VertexMobility& m = mesh.mobility(v);
  switch (m.freedom) {
    case VertexFreedom::Free: return d;
    case VertexFreedom::Planar: return d - dot(d, m.axis) * m.axis;
    case VertexFreedom::Linear: return dot(d, m.axis) * m.axis;
    case VertexFreedom::Curved: {
      const Point3 n = surfaceNormalAt(mesh, v, q);
      return d - dot(d, n) * n;
    }
    case VertexFreedom::OnCurve: {
      const auto& p = mesh.points();
      const Point3 chord = p[m.feature_neighbours[1]] - p[m.feature_neighbours[0]];
      const double length = norm(chord);
      return length > 0 ? (dot(d, chord) / (length * length)) * chord : Point3{0, 0, 0};
    }
    default: return {0, 0, 0};
  }
}

// Where v goes when asked to go to q: q itself, or q put back onto v's curved face or curve.
std::optional<Point3> placed(const ImprovementMesh& mesh, int64_t v, const Point3& q) {
  switch (mesh.mobility(v).freedom) {
    case VertexFreedom::Curved: return mesh.placement()->ontoSurface(v, q);
    case VertexFreedom::OnCurve: return mesh.placement()->ontoCurve(v, q);
    default: return q;
  }
}

}  // namespace

bool smoothVertex(ImprovementMesh& mesh, int64_t v, const SizeCriteria& sizes) {
  const VertexMobility& mobility = mesh.mobility(v);
  if (mobility.freedom == VertexFreedom::Fixed) return false;
  Star star{mesh, v, mesh.tetsOf(v)};
  if (star.tets.empty()) return false;
  auto& p = mesh.points();
  SizeBound bound;
  bound.criteria = &sizes;
  double shortest = std::numeric_limits<double>::infinity();
  for (int64_t t : star.tets) {
    const TetCorners& c = mesh.tet(t);
    bound.include(tetSize(p[c[0]], p[c[1]], p[c[2]], p[c[3]]));
    for (int64_t w : c)
      if (w != v) shortest = std::min(shortest, distance(p[v], p[w]));
  }
  const Point3 start = p[v];
  const double boundarySize = boundarySizeAt(mesh, v, start);
  std::set<int> materials;
  for (int64_t t : star.tets) materials.insert(mesh.material(t));
  double current = star.worstAt(start, &bound);
  if (current < 0) return false;
  // A curved-surface or curve vertex moves only from its place on the model (the snap may
  // have left one off it, where moving it there would have flattened a tet).
  const bool curved = mobility.freedom == VertexFreedom::Curved || mobility.freedom == VertexFreedom::OnCurve;
  if (curved) {
    const std::optional<Point3> here = placed(mesh, v, start);
    if (!here || distance(*here, start) > 1e-9 * shortest) return false;
  }
  Point3 position = start;
  const double h = 1e-7 * shortest;
  // Moves along `direction` by a fifth of the shortest edge, backing off until the worst angle
  // rises; false when no step along it does. On a curved face or curve the step is put back
  // onto it, and refused where that lands far from the step (another face's point was nearer)
  // or moves more of a material's volume than the stage allows.
  auto lineSearch = [&](const Point3& direction) {
    const double length = norm(direction);
    if (!(length > 0)) return false;
    double stepLength = 0.2 * shortest;
    for (int k = 0; k < kStepHalvings; ++k, stepLength *= 0.5) {
      const Point3 step = position + (stepLength / length) * direction;
      // Putting a step back onto a curved face or curve moves it by far less than the step
      // (the sagitta), so a step that does not raise the worst angle before it seldom does
      // after it; the projection (OpenCASCADE on a B-rep) is what costs, so it is skipped then.
      if (curved && star.worstAt(step, nullptr) <= current) continue;
      const std::optional<Point3> q = placed(mesh, v, step);
      if (!q || distance(*q, step) > stepLength) continue;
      const double worst = star.worstAt(*q, &bound);
      if (worst > current && boundarySizesHold(mesh, v, *q, boundarySize, sizes, materials) &&
          (!curved || mesh.volumeFits(star.volumeChange(start, *q)))) {
        position = *q;
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
    if (lineSearch(allowedDirection(mesh, v, position, gradient))) continue;
    // Where two worst angles meet, the gradient of one lowers the other: a compass search
    // along the free axes finds the way out.
    bool moved = false;
    for (int axis = 0; axis < 3 && !moved; ++axis)
      for (double sign : {1.0, -1.0}) {
        Point3 d{0, 0, 0};
        d[axis] = sign;
        if ((moved = lineSearch(allowedDirection(mesh, v, position, d)))) break;
      }
    if (!moved) break;
  }
  if (position == start) return false;
  if (curved) mesh.addVolumeChange(star.volumeChange(start, position));
  p[v] = position;
  mesh.markMoved(v);
  return true;
}

}  // namespace oraclemesh
