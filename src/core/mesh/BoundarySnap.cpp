#include "mesh/BoundarySnap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <unordered_map>
#include <utility>

#include "mesh/Quality.h"
#include "mesh/Topology.h"

namespace oraclemesh {

namespace {

// Whether moving vertex v to `target` would turn one of its (positively oriented) tets flat or
// inside out.
bool degeneratesAnIncidentTet(const TetMesh& mesh, const std::vector<int64_t>& tets, int64_t v, const Point3& target) {
  for (int64_t t : tets) {
    std::array<Point3, 4> corners;
    for (int k = 0; k < 4; ++k) corners[k] = mesh.tets[t][k] == v ? target : mesh.points[mesh.tets[t][k]];
    if (tetVolume(corners[0], corners[1], corners[2], corners[3]) <= 0) return true;
  }
  return false;
}

std::vector<std::vector<int64_t>> tetsOfVertices(const TetMesh& mesh) {
  std::vector<std::vector<int64_t>> tets(mesh.points.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) tets[mesh.tets[t][k]].push_back(static_cast<int64_t>(t));
  return tets;
}

}  // namespace

int64_t removeFlatSurfaceSlivers(TetMesh& mesh, const std::vector<Point3>& target, int64_t& keptOnFeatureEdges) {
  // The outer faces are the boundary triangles with nothing beyond them (mesh.boundary is
  // current when the snap runs).
  std::set<std::array<int64_t, 3>> outer;
  for (const BoundaryTriangle& b : mesh.boundary)
    if (b.material_out == 0) {
      std::array<int64_t, 3> f = b.v;
      std::sort(f.begin(), f.end());
      outer.insert(f);
    }
  auto faceOf = [&](size_t t, int skip) {
    std::array<int64_t, 3> f{};
    int n = 0;
    for (int k = 0; k < 4; ++k)
      if (k != skip) f[n++] = mesh.tets[t][k];
    std::sort(f.begin(), f.end());
    return f;
  };
  std::set<std::array<int64_t, 3>> exposed;  // inner faces of tets removed in this pass
  // Tets left on each feature edge: the last one stays.
  std::unordered_map<uint64_t, int> tetsOnFeatureEdge;
  for (const auto& e : mesh.feature_edges) tetsOnFeatureEdge[undirectedEdgeKey(e[0], e[1])] = 0;
  auto forFeatureEdgesOf = [&](size_t t, auto&& f) {
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        auto it = tetsOnFeatureEdge.find(undirectedEdgeKey(mesh.tets[t][a], mesh.tets[t][b]));
        if (it != tetsOnFeatureEdge.end()) f(it->second);
      }
  };
  for (size_t t = 0; t < mesh.tets.size(); ++t) forFeatureEdgesOf(t, [](int& n) { ++n; });
  std::vector<char> remove(mesh.tets.size(), 0);
  int64_t removed = 0;
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    int outside = 0;
    bool nextToRemoved = false;
    for (int k = 0; k < 4; ++k) {
      const auto f = faceOf(t, k);
      outside += outer.count(f) > 0;
      nextToRemoved |= exposed.count(f) > 0;
    }
    // A neighbour of a removed tet waits for another pass: removing both sides of a face
    // would open the mesh.
    if (outside < 2 || outside > 3 || nextToRemoved) continue;
    const auto& c = mesh.tets[t];
    if (tetVolume(target[c[0]], target[c[1]], target[c[2]], target[c[3]]) > 0) continue;
    bool lastOnFeatureEdge = false;
    forFeatureEdgesOf(t, [&](int& n) { lastOnFeatureEdge |= n == 1; });
    if (lastOnFeatureEdge) {
      ++keptOnFeatureEdges;
      continue;
    }
    forFeatureEdgesOf(t, [](int& n) { --n; });
    remove[t] = 1;
    ++removed;
    for (int k = 0; k < 4; ++k)
      if (!outer.count(faceOf(t, k))) exposed.insert(faceOf(t, k));
  }
  if (removed == 0) return 0;
  size_t kept = 0;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    if (!remove[t]) {
      mesh.tets[kept] = mesh.tets[t];
      mesh.tet_materials[kept] = mesh.tet_materials[t];
      ++kept;
    }
  mesh.tets.resize(kept);
  mesh.tet_materials.resize(kept);
  mesh.boundary = extractBoundary(mesh);
  return removed;
}

BoundarySnapResult snapBoundaryVertices(TetMesh& mesh, const HierarchicalOracle& oracle, const CurveRegistry& curves,
                                        const RunControl& control) {
  BoundarySnapResult result;
  BoundarySnapStatistics& r = result.statistics;
  result.vertex_entry.assign(mesh.points.size(), -1);
  std::vector<char> onBoundary(mesh.points.size(), 0);
  for (const BoundaryTriangle& t : mesh.boundary)
    for (int64_t v : t.v) onBoundary[v] = 1;
  // Where each boundary or feature vertex belongs: on its feature curve, else on the nearest
  // CAD face. Corners are exact curve ends already.
  std::vector<Point3> target = mesh.points;
  std::vector<double> move(mesh.points.size(), 0.0);
  for (size_t v = 0; v < mesh.points.size(); ++v) {
    if (!onBoundary[v] && mesh.vertex_dimension[v] == 3) continue;
    if ((v & 1023) == 0) control.checkpoint();
    // The thesis engine's surface vertices are oracle crossings or projections already: a
    // projection would only find them where they are (implant_in_bone (a): 1,991 vertices
    // moved by at most 2e-13 mm, at 12 % of the job's time).
    if (mesh.vertex_dimension[v] == 2 && !mesh.vertex_boundary_entry.empty() && mesh.vertex_boundary_entry[v] >= 0) {
      result.vertex_entry[v] = mesh.vertex_boundary_entry[v];
      ++r.on_boundary_by_engine;
      continue;
    }
    BoundaryProjection q;
    int entry = -1;
    const int curve = mesh.vertex_curve[v];
    if (mesh.vertex_dimension[v] <= 1 && curve >= 0 && curves.contains(curve)) {
      q = curves.project(curve, mesh.points[v]);
      entry = curves.entryOf(curve);
    }
    if (!std::isfinite(q.distance)) q = oracle.projectOnBoundary(mesh.points[v], &entry);
    result.vertex_entry[v] = entry;
    if (mesh.vertex_dimension[v] == 0) continue;
    if (mesh.vertex_dimension[v] == 3) mesh.vertex_dimension[v] = 2;
    if (!std::isfinite(q.distance) || q.distance == 0) continue;
    target[v] = q.point;
    move[v] = q.distance;
  }
  r.slivers_removed = removeFlatSurfaceSlivers(mesh, target, r.slivers_kept_on_feature_edges);
  const std::vector<std::vector<int64_t>> tetsOfVertex = tetsOfVertices(mesh);
  // A move that would fold a tet now may be fine once the tet's other corners have moved
  // (neighbouring nodes on two curves meeting at a small angle): passes over the nodes still
  // off their target repeat, in index order, until one moves none.
  std::vector<int64_t> pending;
  for (size_t v = 0; v < mesh.points.size(); ++v)
    if (move[v] != 0) pending.push_back(static_cast<int64_t>(v));
  for (size_t before = pending.size() + 1; !pending.empty() && pending.size() < before;) {
    before = pending.size();
    std::vector<int64_t> blocked;
    for (int64_t v : pending) {
      if (degeneratesAnIncidentTet(mesh, tetsOfVertex[v], v, target[v])) {
        blocked.push_back(v);
        continue;
      }
      r.max_move = std::max(r.max_move, move[v]);
      ++r.moved;
      mesh.points[v] = target[v];
    }
    pending.swap(blocked);
  }
  result.distance_kept.assign(mesh.points.size(), 0.0);
  for (int64_t v : pending) {
    ++r.kept_off_surface;
    result.distance_kept[v] = move[v];
    if (move[v] > r.max_distance_kept) {
      r.max_distance_kept = move[v];
      r.worst_kept = mesh.points[v];
    }
  }
  return result;
}

void BoundarySnapResult::renumber(const std::vector<int64_t>& previousIndex) {
  if (previousIndex.empty()) return;
  std::vector<int> entries;
  std::vector<double> kept;
  // A vertex the improvement stage inserted (-1) is interior: no entry, nothing kept off.
  for (int64_t v : previousIndex) {
    if (!vertex_entry.empty()) entries.push_back(v >= 0 && static_cast<size_t>(v) < vertex_entry.size() ? vertex_entry[v] : -1);
    if (!distance_kept.empty()) kept.push_back(v >= 0 && static_cast<size_t>(v) < distance_kept.size() ? distance_kept[v] : 0.0);
  }
  vertex_entry = std::move(entries);
  distance_kept = std::move(kept);
}

}  // namespace oraclemesh
