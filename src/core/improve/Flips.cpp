#include "improve/Flips.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <limits>
#include <map>
#include <set>

#include "Error.h"
#include "mesh/Quality.h"

namespace oraclemesh {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Face = std::array<int64_t, 3>;
using Edge = std::array<int64_t, 2>;
using Tet = std::array<int64_t, 4>;

Face sortedFace(int64_t a, int64_t b, int64_t c) {
  Face f{a, b, c};
  std::sort(f.begin(), f.end());
  return f;
}

Edge sortedEdge(int64_t a, int64_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

CGAL::Orientation orientation(const std::vector<Point3>& p, const Tet& t) {
  auto k = [&](int64_t i) { return Kernel::Point_3(p[i][0], p[i][1], p[i][2]); };
  return CGAL::orientation(k(t[0]), k(t[1]), k(t[2]), k(t[3]));
}

double minDihedral(const std::vector<Point3>& p, const Tet& t) {
  const auto angles = dihedralAngles(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
  return *std::min_element(angles.begin(), angles.end());
}


// Circumradius and radius-edge ratio, so a flip can be held to the worst of what it replaces:
// cells that met the engine's size and shape criteria still meet them afterwards.
struct Shape {
  double radius = 0, ratio = 0;
};

Shape shape(const std::vector<Point3>& p, const Tet& t) {
  double shortest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) shortest = std::min(shortest, distance(p[t[i]], p[t[j]]));
  const double ratio = radiusEdgeRatio(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
  return {ratio * shortest, ratio};
}

bool withinWorstOf(const std::vector<Point3>& p, const std::vector<Tet>& made, const std::vector<Tet>& old) {
  Shape worst;
  for (const Tet& t : old) {
    const Shape s = shape(p, t);
    worst = {std::max(worst.radius, s.radius), std::max(worst.ratio, s.ratio)};
  }
  for (const Tet& t : made) {
    const Shape s = shape(p, t);
    if (!(s.radius <= worst.radius && s.ratio <= worst.ratio)) return false;
  }
  return true;
}

struct Pass {
  TetMesh& mesh;
  std::set<Face> protected_faces;
  std::set<Edge> protected_edges;
  std::map<Face, std::vector<size_t>> face_tets;
  std::map<Edge, std::vector<size_t>> edge_tets;
  std::vector<char> touched;
  std::vector<Tet> new_tets;
  std::vector<int> new_materials;
  FlipStats& stats;

  Pass(TetMesh& m, FlipStats& s) : mesh(m), stats(s) {
    for (const auto& b : mesh.boundary) protected_faces.insert(sortedFace(b.v[0], b.v[1], b.v[2]));
    for (const auto& e : mesh.feature_edges) protected_edges.insert(sortedEdge(e[0], e[1]));
    for (size_t t = 0; t < mesh.tets.size(); ++t) {
      const Tet& v = mesh.tets[t];
      for (int i = 0; i < 4; ++i) face_tets[sortedFace(v[(i + 1) % 4], v[(i + 2) % 4], v[(i + 3) % 4])].push_back(t);
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) edge_tets[sortedEdge(v[i], v[j])].push_back(t);
    }
    touched.assign(mesh.tets.size(), 0);
  }

  bool usable(const std::vector<size_t>& tets, int material) const {
    for (size_t t : tets)
      if (touched[t] || mesh.tet_materials[t] != material) return false;
    return true;
  }

  bool keepsCriteria(const std::vector<size_t>& old, const std::vector<Tet>& made) const {
    std::vector<Tet> replaced;
    for (size_t t : old) replaced.push_back(mesh.tets[t]);
    return withinWorstOf(mesh.points, made, replaced);
  }

  void commit(const std::vector<size_t>& old, const std::vector<Tet>& made, int material) {
    for (size_t t : old) touched[t] = 1;
    for (const Tet& t : made) {
      new_tets.push_back(t);
      new_materials.push_back(material);
    }
  }

  // 2-3: the face shared by tets t0 and its neighbour becomes the edge between their apexes.
  bool try23(size_t t0, const Face& f) {
    const auto it = face_tets.find(f);
    if (it == face_tets.end() || it->second.size() != 2 || protected_faces.count(f)) return false;
    const int material = mesh.tet_materials[t0];
    if (!usable(it->second, material)) return false;
    auto apex = [&](size_t t) {
      for (int64_t v : mesh.tets[t])
        if (v != f[0] && v != f[1] && v != f[2]) return v;
      return int64_t{-1};
    };
    const int64_t a = apex(it->second[0]), b = apex(it->second[1]);
    const double before = std::min(minDihedral(mesh.points, mesh.tets[it->second[0]]),
                                   minDihedral(mesh.points, mesh.tets[it->second[1]]));
    // The new edge must pierce the face's interior: the three new tets then share one strict
    // orientation (else they would overlap or leave a gap); all negative means a, b swapped.
    std::vector<Tet> made;
    for (int i = 0; i < 3; ++i) made.push_back(Tet{a, b, f[i], f[(i + 1) % 3]});
    const CGAL::Orientation first = orientation(mesh.points, made[0]);
    if (first == CGAL::COPLANAR) return false;
    double after = std::numeric_limits<double>::infinity();
    for (Tet& t : made) {
      if (orientation(mesh.points, t) != first) return false;
      if (first == CGAL::NEGATIVE) std::swap(t[0], t[1]);
      after = std::min(after, minDihedral(mesh.points, t));
    }
    if (!(after > before) || !keepsCriteria(it->second, made)) return false;
    commit(it->second, made, material);
    ++stats.flips23;
    return true;
  }

  // 3-2: an interior edge with exactly three tets around it becomes the face of its ring.
  bool try32(size_t t0, const Edge& e) {
    const auto it = edge_tets.find(e);
    if (it == edge_tets.end() || it->second.size() != 3 || protected_edges.count(e)) return false;
    const int material = mesh.tet_materials[t0];
    if (!usable(it->second, material)) return false;
    std::set<int64_t> ring;
    double before = std::numeric_limits<double>::infinity();
    for (size_t t : it->second) {
      before = std::min(before, minDihedral(mesh.points, mesh.tets[t]));
      for (int64_t v : mesh.tets[t])
        if (v != e[0] && v != e[1]) ring.insert(v);
      // Every face around the edge must be shared by two of the three tets: a closed ring,
      // so the edge is not on the boundary.
      for (int64_t v : mesh.tets[t]) {
        if (v == e[0] || v == e[1]) continue;
        const Face f = sortedFace(e[0], e[1], v);
        if (protected_faces.count(f) || face_tets[f].size() != 2) return false;
      }
    }
    if (ring.size() != 3) return false;
    const std::vector<int64_t> r(ring.begin(), ring.end());
    // The closed ring makes the edge's line cross the ring triangle; the ring's plane must
    // also separate the edge's ends strictly, or the two new tets would overlap or be flat.
    std::vector<Tet> made{Tet{r[0], r[1], r[2], e[0]}, Tet{r[0], r[1], r[2], e[1]}};
    const CGAL::Orientation o0 = orientation(mesh.points, made[0]), o1 = orientation(mesh.points, made[1]);
    if (o0 == CGAL::COPLANAR || o1 == CGAL::COPLANAR || o0 == o1) return false;
    std::swap((o0 == CGAL::NEGATIVE ? made[0] : made[1])[0], (o0 == CGAL::NEGATIVE ? made[0] : made[1])[1]);
    double after = std::numeric_limits<double>::infinity();
    for (const Tet& t : made) after = std::min(after, minDihedral(mesh.points, t));
    if (!(after > before) || !keepsCriteria(it->second, made)) return false;
    commit(it->second, made, material);
    ++stats.flips32;
    return true;
  }

  int64_t run() {
    std::vector<std::pair<double, size_t>> order;
    for (size_t t = 0; t < mesh.tets.size(); ++t) order.push_back({minDihedral(mesh.points, mesh.tets[t]), t});
    std::sort(order.begin(), order.end());
    int64_t done = 0;
    for (const auto& [quality, t] : order) {
      if (touched[t]) continue;
      const Tet v = mesh.tets[t];
      bool flipped = false;
      for (int i = 0; i < 4 && !flipped; ++i)
        for (int j = i + 1; j < 4 && !flipped; ++j) flipped = try32(t, sortedEdge(v[i], v[j]));
      for (int i = 0; i < 4 && !flipped; ++i)
        flipped = try23(t, sortedFace(v[(i + 1) % 4], v[(i + 2) % 4], v[(i + 3) % 4]));
      done += flipped;
    }
    std::vector<Tet> tets;
    std::vector<int> materials;
    for (size_t t = 0; t < mesh.tets.size(); ++t)
      if (!touched[t]) {
        tets.push_back(mesh.tets[t]);
        materials.push_back(mesh.tet_materials[t]);
      }
    tets.insert(tets.end(), new_tets.begin(), new_tets.end());
    materials.insert(materials.end(), new_materials.begin(), new_materials.end());
    mesh.tets = std::move(tets);
    mesh.tet_materials = std::move(materials);
    return done;
  }
};

double meshMinDihedral(const TetMesh& mesh) {
  double m = 180;
  for (const Tet& t : mesh.tets) m = std::min(m, minDihedral(mesh.points, t));
  return m;
}

}  // namespace

FlipStats improveByFlips(TetMesh& mesh, int max_passes) {
  if (mesh.order() != 1) throw Error("improveByFlips: second-order mesh; improve before placing mid nodes");
  FlipStats stats;
  stats.min_dihedral_before = meshMinDihedral(mesh);
  for (int pass = 0; pass < max_passes; ++pass) {
    ++stats.passes;
    if (Pass(mesh, stats).run() == 0) break;
  }
  stats.min_dihedral_after = meshMinDihedral(mesh);
  return stats;
}

}  // namespace oraclemesh
