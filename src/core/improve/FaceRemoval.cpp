#include "improve/FaceRemoval.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace oraclemesh {

bool removeFace(ImprovementMesh& mesh, int64_t a, int64_t b, int64_t c) {
  if (mesh.isProtectedFace(a, b, c)) return false;
  const std::vector<int64_t> tets = mesh.tetsWithFace(a, b, c);
  if (tets.size() != 2 || mesh.material(tets[0]) != mesh.material(tets[1])) return false;
  const auto& p = mesh.points();
  auto apex = [&](int64_t t) {
    for (int64_t v : mesh.tet(t))
      if (v != a && v != b && v != c) return v;
    return int64_t{-1};
  };
  int64_t top = apex(tets[0]), bottom = apex(tets[1]);
  const int64_t face[3] = {a, b, c};
  // Name the apexes so that (a, b, c, top) is positive; then (top, bottom, x, y) is positive
  // for consecutive x, y of (a, c, b).
  if (exactOrientation(p[a], p[b], p[c], p[top]) < 0) std::swap(top, bottom);
  std::vector<TetCorners> made;
  const int64_t order[3] = {face[0], face[2], face[1]};
  for (int i = 0; i < 3; ++i) made.push_back({top, bottom, order[i], order[(i + 1) % 3]});
  SizeBound bound;
  double before = std::numeric_limits<double>::infinity();
  for (int64_t t : tets) {
    const TetCorners& k = mesh.tet(t);
    bound.include(tetSize(p[k[0]], p[k[1]], p[k[2]], p[k[3]]));
    before = std::min(before, mesh.quality(t));
  }
  if (mesh.hasEdge(top, bottom)) return false;
  double after = std::numeric_limits<double>::infinity();
  for (const TetCorners& t : made) {
    if (exactOrientation(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) <= 0) return false;
    if (!bound.admits(tetSize(p[t[0]], p[t[1]], p[t[2]], p[t[3]]))) return false;
    after = std::min(after, smallestDihedral(p, t));
  }
  if (!(after > before)) return false;
  mesh.replace(tets, made, mesh.material(tets[0]));
  return true;
}

}  // namespace oraclemesh
