#include "improve/SurfaceFlip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <vector>

#include "improve/EdgeRemoval.h"

namespace oraclemesh {
namespace {

// "In one plane" as the vertex classification has it: the snap puts vertices on planar faces
// to rounding, far inside this; a curved face's chords are far outside it.
constexpr double kFlatTolerance = 1e-9;

struct Side {
  std::vector<int64_t> tets;
  std::vector<TetCorners> made;
};

}  // namespace

bool flipSurfaceEdge(ImprovementMesh& mesh, int64_t a, int64_t b, const SizeCriteria& sizes, double curvedFlatness) {
  if (mesh.isProtectedEdge(a, b)) return false;
  const std::vector<int64_t> around = mesh.tetsAroundEdge(a, b);
  // The link vertices whose face with ab is on the surface: exactly c and d.
  std::vector<int64_t> surface;
  std::map<int, Side> sides;
  double before = std::numeric_limits<double>::infinity();
  for (int64_t t : around) {
    sides[mesh.material(t)].tets.push_back(t);
    before = std::min(before, mesh.quality(t));
    for (int64_t v : mesh.tet(t))
      if (v != a && v != b && mesh.isProtectedFace(a, b, v) &&
          std::find(surface.begin(), surface.end(), v) == surface.end())
        surface.push_back(v);
  }
  if (surface.size() != 2 || sides.empty() || sides.size() > 2) return false;
  const int64_t c = surface[0], d = surface[1];
  if (mesh.hasEdge(c, d)) return false;

  const auto& p = mesh.points();
  // The quad's normal: abc's and abd's, turned one way (c and d lie on either side of ab).
  const Point3 normal = cross(p[b] - p[a], p[c] - p[a]) - cross(p[b] - p[a], p[d] - p[a]);
  const double reach = std::max({distance(p[a], p[b]), distance(p[a], p[c]), distance(p[b], p[c]),
                                 distance(p[a], p[d]), distance(p[b], p[d]), distance(p[c], p[d])});
  if (!(norm(normal) > 0)) return false;
  const Point3 unitNormal = unit(normal);
  const double offPlane = std::max(std::abs(dot(unitNormal, p[c] - p[a])), std::abs(dot(unitNormal, p[d] - p[a])));
  const bool planar = offPlane <= kFlatTolerance * reach;
  if (!planar && !(mesh.placement() && offPlane <= curvedFlatness * reach)) return false;
  // Convex: c and d on either side of ab, a and b on either side of cd (seen along the normal).
  auto side = [&](const Point3& x, const Point3& y, const Point3& z) { return dot(normal, cross(y - x, z - x)); };
  if (!(side(p[a], p[b], p[c]) * side(p[a], p[b], p[d]) < 0)) return false;
  if (!(side(p[c], p[d], p[a]) * side(p[c], p[d], p[b]) < 0)) return false;

  // On a curved piece the new diagonal no longer than the old (a chord's distance from the face
  // grows with its length); in a plane the new triangles no larger in circumradius than the old
  // or within the facet size.
  if (!planar && distance(p[c], p[d]) > distance(p[a], p[b])) return false;
  if (planar) {
    std::set<int> materials;
    for (const auto& [material, s] : sides) materials.insert(material);
    const double oldRadius = std::max(triangleCircumradius(p[a], p[b], p[c]), triangleCircumradius(p[a], p[b], p[d]));
    for (int64_t x : {a, b}) {
      const double radius = triangleCircumradius(p[x], p[c], p[d]);
      if (radius > oldRadius && !(radius <= sizes.strictestFacetSize(materials, (1.0 / 3) * (p[x] + p[c] + p[d]))))
        return false;
    }
  }

  for (auto& [material, s] : sides) {
    SizeBound bound;
    bound.criteria = &sizes;
    for (int64_t t : s.tets) {
      const TetCorners& k = mesh.tet(t);
      bound.include(tetSize(p[k[0]], p[k[1]], p[k[2]], p[k[3]]));
    }
    std::array<int64_t, 2> ends{-1, -1};
    const double worst = triangulateEdgeFan(mesh, a, b, s.tets, bound, material, s.made, ends);
    // Each fan must run between c and d, or the surface faces at ab were not these two.
    if (!(worst > before) || std::minmax(ends[0], ends[1]) != std::minmax(c, d)) return false;
  }
  // On a curved piece the new chords cut the face elsewhere: the sliver abcd changes sides,
  // counted against each material's curved-move volume bound.
  std::map<int, double> change;
  if (!planar) {
    for (const auto& [material, s] : sides) {
      double dv = 0;
      for (const TetCorners& t : s.made) dv += tetVolume(p, t);
      for (int64_t t : s.tets) dv -= tetVolume(p, mesh.tet(t));
      change[material] = dv;
    }
    if (!mesh.volumeFits(change)) return false;
  }
  for (const auto& [material, s] : sides) mesh.replace(s.tets, s.made, material);
  mesh.flipProtectedFaces(a, b, c, d);
  mesh.addVolumeChange(change);
  return true;
}

}  // namespace oraclemesh
