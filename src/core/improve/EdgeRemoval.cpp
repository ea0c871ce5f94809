#include "improve/EdgeRemoval.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace oraclemesh {
namespace {

constexpr double kWorst = -std::numeric_limits<double>::infinity();

// The link vertices around ab, ordered so that (a, b, r_i, r_{i+1}) is positive, as every tet
// of the mesh is: a closed ring (one vertex per tet) or, for the tets on one side of an edge of
// the boundary, an open fan from the one link vertex no tet precedes (one vertex more). Empty
// when the tets make neither, or pass a vertex twice.
std::vector<int64_t> linkAround(const ImprovementMesh& mesh, int64_t a, int64_t b, const std::vector<int64_t>& tets,
                                bool closed) {
  std::vector<std::array<int64_t, 2>> links;
  const auto& p = mesh.points();
  for (int64_t t : tets) {
    std::array<int64_t, 2> cd{-1, -1};
    int k = 0;
    for (int64_t v : mesh.tet(t))
      if (v != a && v != b) cd[k++] = v;
    if (exactOrientation(p[a], p[b], p[cd[0]], p[cd[1]]) < 0) std::swap(cd[0], cd[1]);
    links.push_back(cd);
  }
  auto linkFrom = [&](int64_t v) {
    return std::find_if(links.begin(), links.end(), [&](const auto& l) { return l[0] == v; });
  };
  int64_t start = links.front()[0];
  if (!closed) {
    start = -1;
    for (const auto& l : links) {
      const bool preceded = std::any_of(links.begin(), links.end(), [&](const auto& m) { return m[1] == l[0]; });
      if (preceded) continue;
      if (start >= 0) return {};
      start = l[0];
    }
    if (start < 0) return {};
  }
  std::vector<int64_t> ring{start};
  for (size_t step = 0; step < links.size(); ++step) {
    const auto next = linkFrom(ring.back());
    if (next == links.end()) return {};
    ring.push_back((*next)[1]);
  }
  if (closed) {
    if (ring.back() != ring.front()) return {};
    ring.pop_back();
  }
  std::vector<int64_t> distinct = ring;
  std::sort(distinct.begin(), distinct.end());
  if (std::adjacent_find(distinct.begin(), distinct.end()) != distinct.end()) return {};
  return ring;
}

struct RingTriangulation {
  const ImprovementMesh& mesh;
  int64_t a, b;
  const std::vector<int64_t>& ring;
  const SizeBound& bound;
  int material;
  int n;
  // best[i][j]: worst quality of the best triangulation of the sub-polygon r_i..r_j; apex[i][j]
  // the ring index k of the triangle (i, k, j) that achieves it.
  double best[kMaxEdgeRemovalRing][kMaxEdgeRemovalRing];
  int apex[kMaxEdgeRemovalRing][kMaxEdgeRemovalRing];

  // The two tets over triangle (i, k, j), i < k < j: the ring runs clockwise seen from a.
  std::array<TetCorners, 2> tetsOver(int i, int k, int j) const {
    return {TetCorners{ring[i], ring[j], ring[k], a}, TetCorners{ring[i], ring[k], ring[j], b}};
  }

  double triangleQuality(int i, int k, int j) const {
    const auto& p = mesh.points();
    double q = std::numeric_limits<double>::infinity();
    for (const TetCorners& t : tetsOver(i, k, j)) {
      if (exactOrientation(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) <= 0) return kWorst;
      if (!bound.admits(material, p[t[0]], p[t[1]], p[t[2]], p[t[3]])) return kWorst;
      q = std::min(q, smallestDihedral(p, t));
    }
    return q;
  }

  double solve() {
    for (int i = 0; i + 1 < n; ++i) best[i][i + 1] = std::numeric_limits<double>::infinity();
    for (int span = 2; span < n; ++span)
      for (int i = 0; i + span < n; ++i) {
        const int j = i + span;
        best[i][j] = kWorst;
        apex[i][j] = -1;
        for (int k = i + 1; k < j; ++k) {
          const double q = std::min({best[i][k], best[k][j], triangleQuality(i, k, j)});
          if (q > best[i][j]) {
            best[i][j] = q;
            apex[i][j] = k;
          }
        }
      }
    return best[0][n - 1];
  }

  void collect(int i, int j, std::vector<TetCorners>& out, std::vector<std::array<int64_t, 2>>& diagonals) const {
    if (j - i < 2) return;
    const int k = apex[i][j];
    for (const TetCorners& t : tetsOver(i, k, j)) out.push_back(t);
    if (k - i >= 2) diagonals.push_back({ring[i], ring[k]});
    if (j - k >= 2) diagonals.push_back({ring[k], ring[j]});
    collect(i, k, out, diagonals);
    collect(k, j, out, diagonals);
  }
};

// The best triangulation of the polygon `ring` (closed by its edge r_{n-1} r_0) joined to a
// and b; -infinity when there is none.
double triangulateLink(const ImprovementMesh& mesh, int64_t a, int64_t b, const std::vector<int64_t>& ring,
                       const SizeBound& bound, int material, std::vector<TetCorners>& made) {
  const int n = static_cast<int>(ring.size());
  if (n < 3 || n > kMaxEdgeRemovalRing) return kWorst;
  RingTriangulation triangulation{mesh, a, b, ring, bound, material, n, {}, {}};
  const double worst = triangulation.solve();
  if (worst == kWorst) return kWorst;
  std::vector<std::array<int64_t, 2>> diagonals;
  made.clear();
  triangulation.collect(0, n - 1, made, diagonals);
  // A diagonal that is already an edge elsewhere would be a second copy of it.
  for (const auto& d : diagonals)
    if (mesh.hasEdge(d[0], d[1])) return kWorst;
  return worst;
}

}  // namespace

double triangulateEdgeRing(const ImprovementMesh& mesh, int64_t a, int64_t b, const std::vector<int64_t>& tets,
                           const SizeBound& bound, int material, std::vector<TetCorners>& made) {
  if (tets.size() < 3 || tets.size() > kMaxEdgeRemovalRing) return kWorst;
  const std::vector<int64_t> ring = linkAround(mesh, a, b, tets, true);
  if (ring.size() != tets.size()) return kWorst;
  return triangulateLink(mesh, a, b, ring, bound, material, made);
}

double triangulateEdgeFan(const ImprovementMesh& mesh, int64_t a, int64_t b, const std::vector<int64_t>& tets,
                          const SizeBound& bound, int material, std::vector<TetCorners>& made,
                          std::array<int64_t, 2>& ends) {
  if (tets.empty() || tets.size() + 1 > kMaxEdgeRemovalRing) return kWorst;
  const std::vector<int64_t> fan = linkAround(mesh, a, b, tets, false);
  if (fan.size() != tets.size() + 1) return kWorst;
  ends = {fan.front(), fan.back()};
  return triangulateLink(mesh, a, b, fan, bound, material, made);
}

int removeEdge(ImprovementMesh& mesh, int64_t a, int64_t b, const SizeCriteria& sizes) {
  if (mesh.isProtectedEdge(a, b)) return 0;
  const std::vector<int64_t> tets = mesh.tetsAroundEdge(a, b);
  const int n = static_cast<int>(tets.size());
  if (n < 3 || n > kMaxEdgeRemovalRing) return 0;
  const int material = mesh.material(tets.front());
  double before = std::numeric_limits<double>::infinity();
  SizeBound bound;
  bound.criteria = &sizes;
  const auto& p = mesh.points();
  for (int64_t t : tets) {
    if (mesh.material(t) != material) return 0;
    const TetCorners& c = mesh.tet(t);
    before = std::min(before, mesh.quality(t));
    bound.include(tetSize(p[c[0]], p[c[1]], p[c[2]], p[c[3]]));
    for (int64_t v : c)
      if (v != a && v != b && mesh.isProtectedFace(a, b, v)) return 0;
  }
  std::vector<TetCorners> made;
  if (!(triangulateEdgeRing(mesh, a, b, tets, bound, material, made) > before)) return 0;
  mesh.replace(tets, made, material);
  return n;
}

}  // namespace oraclemesh
