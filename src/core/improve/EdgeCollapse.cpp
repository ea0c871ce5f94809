#include "improve/EdgeCollapse.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <vector>

#include "mesh/Quality.h"

namespace oraclemesh {
namespace {

// Stands for the outside in the closed stars: a face on the outer boundary is a tet with it.
constexpr int64_t kInfinity = -2;

using Triple = std::array<int64_t, 3>;
using Pair = std::array<int64_t, 2>;

Triple sorted(Triple t) {
  std::sort(t.begin(), t.end());
  return t;
}

Pair sorted(int64_t a, int64_t b) { return {std::min(a, b), std::max(a, b)}; }

// The link of a vertex in a complex, as the simplices opposite it: triangles (of tets), edges
// and vertices.
struct Link {
  std::set<Triple> triangles;
  std::set<Pair> edges;
  std::set<int64_t> vertices;

  void addTriangle(const Triple& t) {
    triangles.insert(sorted(t));
    addEdge(t[0], t[1]);
    addEdge(t[1], t[2]);
    addEdge(t[0], t[2]);
  }
  void addEdge(int64_t a, int64_t b) {
    edges.insert(sorted(a, b));
    vertices.insert(a);
    vertices.insert(b);
  }
};

// The link of w in the tets closed by the vertex at infinity.
Link tetLink(const ImprovementMesh& mesh, int64_t w) {
  Link link;
  for (int64_t t : mesh.tetsOf(w)) {
    Triple rest;
    int k = 0;
    for (int64_t x : mesh.tet(t))
      if (x != w) rest[k++] = x;
    link.addTriangle(rest);
  }
  for (const Triple& f : mesh.outerFacesAt(w)) {
    Triple rest{kInfinity, kInfinity, kInfinity};
    int k = 0;
    for (int64_t x : f)
      if (x != w) rest[k++] = x;
    link.addTriangle(rest);  // two corners of the face and infinity
  }
  return link;
}

// The link of w in the boundary and interface triangles: edges and vertices.
Link surfaceLink(const ImprovementMesh& mesh, int64_t w) {
  Link link;
  for (const Triple& f : mesh.facesAt(w)) {
    if (!mesh.isProtectedFace(f[0], f[1], f[2])) continue;
    Pair rest;
    int k = 0;
    for (int64_t x : f)
      if (x != w) rest[k++] = x;
    link.addEdge(rest[0], rest[1]);
  }
  return link;
}

template <class T>
bool intersectionWithin(const std::set<T>& a, const std::set<T>& b, const std::set<T>& allowed) {
  for (const T& x : a)
    if (b.count(x) && !allowed.count(x)) return false;
  return true;
}

// Lk(u) ∩ Lk(v) = Lk(uv) in the tets, in the protected triangles and in the feature edges: the
// collapse then leaves a mesh (Dey, Edelsbrunner et al., "Topology preserving edge
// contraction", 1999), and no boundary, interface or curve is pinched or doubled.
bool linkConditionHolds(const ImprovementMesh& mesh, int64_t v, int64_t u) {
  const Link lu = tetLink(mesh, u), lv = tetLink(mesh, v);
  Link edgeLink;  // Lk(uv): what is opposite uv in the tets around it
  for (const Triple& t : lu.triangles)
    if (std::find(t.begin(), t.end(), v) != t.end()) {
      Pair rest{-1, -1};
      int k = 0;
      for (int64_t x : t)
        if (x != v) rest[k++] = x;
      edgeLink.addEdge(rest[0], rest[1]);
    }
  for (const Triple& t : lu.triangles)
    if (lv.triangles.count(t)) return false;
  if (!intersectionWithin(lu.edges, lv.edges, edgeLink.edges)) return false;
  if (!intersectionWithin(lu.vertices, lv.vertices, edgeLink.vertices)) return false;

  const Link su = surfaceLink(mesh, u), sv = surfaceLink(mesh, v);
  std::set<int64_t> surfaceEdgeLink;  // third corners of the protected triangles at uv
  for (const Pair& e : su.edges)
    if (e[0] == v || e[1] == v) surfaceEdgeLink.insert(e[0] == v ? e[1] : e[0]);
  for (const Pair& e : su.edges)
    if (sv.edges.count(e)) return false;
  if (!intersectionWithin(su.vertices, sv.vertices, surfaceEdgeLink)) return false;

  // Feature edges: u and v share no curve neighbour (a curve would close into a loop of two).
  for (int64_t t : mesh.tetsOf(v))
    for (int64_t x : mesh.tet(t))
      if (x != u && x != v && mesh.isProtectedEdge(v, x) && mesh.isProtectedEdge(u, x)) return false;
  return true;
}

// Whether v may go onto u without leaving its place in the model (EdgeCollapse.h).
bool staysInPlace(const ImprovementMesh& mesh, int64_t v, int64_t u, const SizeCriteria& sizes) {
  const VertexMobility& m = mesh.mobility(v);
  switch (m.freedom) {
    case VertexFreedom::Free: return true;
    case VertexFreedom::Planar:
    case VertexFreedom::Curved:
      for (const auto& t : m.boundary_triangles)
        if (std::find(t.begin(), t.end(), u) != t.end()) return true;
      return false;
    case VertexFreedom::Linear:
    case VertexFreedom::OnCurve: {
      if (!sizes.edge || (m.feature_neighbours[0] != u && m.feature_neighbours[1] != u)) return false;
      const int64_t w = m.feature_neighbours[0] == u ? m.feature_neighbours[1] : m.feature_neighbours[0];
      const auto& p = mesh.points();
      return distance(p[u], p[w]) <= sizes.edge(0.5 * (p[u] + p[w]));
    }
    default: return false;
  }
}

}  // namespace

bool collapseEdge(ImprovementMesh& mesh, int64_t v, int64_t u, const SizeCriteria& sizes) {
  if (v == u || mesh.removed(v) || mesh.removed(u) || !mesh.hasEdge(v, u)) return false;
  if (!staysInPlace(mesh, v, u, sizes)) return false;
  const auto& p = mesh.points();
  SizeBound bound;
  bound.criteria = &sizes;
  double before = std::numeric_limits<double>::infinity();
  for (int64_t t : mesh.tetsOf(v)) {
    const TetCorners& c = mesh.tet(t);
    bound.include(tetSize(p[c[0]], p[c[1]], p[c[2]], p[c[3]]));
    before = std::min(before, mesh.quality(t));
  }
  double after = std::numeric_limits<double>::infinity();
  // Each material's volume change: none but rounding where v stays in its plane or line (the
  // tets around v fill the same region after), the chords' on a curved face or curve.
  const bool curved =
      mesh.mobility(v).freedom == VertexFreedom::Curved || mesh.mobility(v).freedom == VertexFreedom::OnCurve;
  std::map<int, double> volumeChange;
  double starVolume = 0;
  for (int64_t t : mesh.tetsOf(v)) {
    TetCorners c = mesh.tet(t);
    const double volume = tetVolume(p[c[0]], p[c[1]], p[c[2]], p[c[3]]);
    volumeChange[mesh.material(t)] -= volume;
    starVolume += volume;
    if (std::find(c.begin(), c.end(), u) != c.end()) continue;  // goes
    for (int64_t& x : c)
      if (x == v) x = u;
    volumeChange[mesh.material(t)] += tetVolume(p[c[0]], p[c[1]], p[c[2]], p[c[3]]);
    if (exactOrientation(p[c[0]], p[c[1]], p[c[2]], p[c[3]]) <= 0) return false;
    if (!bound.admits(mesh.material(t), p[c[0]], p[c[1]], p[c[2]], p[c[3]])) return false;
    after = std::min(after, smallestDihedral(p, c));
    if (!(after > before)) return false;
  }
  if (!curved)
    for (const auto& [material, change] : volumeChange)
      if (std::abs(change) > 1e-9 * starVolume) return false;
  // The facet size: a renamed boundary or interface triangle within the strictest facet size of
  // the materials at v, or no larger than the largest at v.
  std::set<int> materials;
  for (int64_t t : mesh.tetsOf(v)) materials.insert(mesh.material(t));
  const Link surface = surfaceLink(mesh, v);
  double largest = 0;
  for (const Pair& e : surface.edges) largest = std::max(largest, triangleCircumradius(p[v], p[e[0]], p[e[1]]));
  for (const Pair& e : surface.edges) {
    if (e[0] == u || e[1] == u) continue;
    const double facetSize = curved ? 0 : sizes.strictestFacetSize(materials, (1.0 / 3) * (p[u] + p[e[0]] + p[e[1]]));
    if (triangleCircumradius(p[u], p[e[0]], p[e[1]]) > std::max(largest, facetSize)) return false;
  }
  if (curved && !mesh.volumeFits(volumeChange)) return false;
  if (!linkConditionHolds(mesh, v, u)) return false;
  if (curved) mesh.addVolumeChange(volumeChange);
  mesh.collapse(v, u);
  return true;
}

}  // namespace oraclemesh
