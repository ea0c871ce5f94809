#include "mesh/SecondOrder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "mesh/Quality.h"
#include "mesh/Topology.h"

namespace oraclemesh {

namespace {

// A curved tet must keep at least this fraction of its straight-sided Jacobian determinant
// (at corners, centroid and integration points). Kept low on purpose: a mid node left off the CAD face is missed
// by FreeCAD's constraint-node search, and a flat tet whose four corners lie on one curved
// face (two opposite edges on the face) keeps only ~0.5% of it once both edges follow the
// face, while staying valid.
constexpr double kMinJacobianFraction = 0.002;

struct EdgeHash {
  size_t operator()(const std::array<int64_t, 2>& e) const {
    uint64_t x = static_cast<uint64_t>(e[0]) * 0x9e3779b97f4a7c15ULL ^ static_cast<uint64_t>(e[1]);
    x ^= x >> 31;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 29;
    return static_cast<size_t>(x);
  }
};

using EdgeKey = std::array<int64_t, 2>;  // smaller vertex index first
EdgeKey edgeKey(int64_t a, int64_t b) { return a < b ? EdgeKey{a, b} : EdgeKey{b, a}; }

}  // namespace

int makeSecondOrder(TetMesh& mesh, const MidNodePlacer& place) {
  requireConsistentIndices(mesh);
  if (mesh.order() == 2 || mesh.tets.empty()) return 0;

  // Number the edges: first met, first numbered.
  std::unordered_map<EdgeKey, int64_t, EdgeHash> edgeIndex;
  edgeIndex.reserve(mesh.tets.size() * 2);
  std::vector<EdgeKey> edges;
  std::vector<std::array<int64_t, 6>> edgesOfTet(mesh.tets.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int e = 0; e < 6; ++e) {
      const EdgeKey key = edgeKey(mesh.tets[t][kTetEdgeCorners[e][0]], mesh.tets[t][kTetEdgeCorners[e][1]]);
      auto [it, added] = edgeIndex.emplace(key, static_cast<int64_t>(edges.size()));
      if (added) edges.push_back(key);
      edgesOfTet[t][e] = it->second;
    }

  // Tets around each edge (compressed rows), to re-check exactly the tets a mid node bends.
  std::vector<int64_t> tetsOfEdgeStart(edges.size() + 1, 0);
  for (const auto& row : edgesOfTet)
    for (int64_t e : row) ++tetsOfEdgeStart[e + 1];
  for (size_t e = 0; e < edges.size(); ++e) tetsOfEdgeStart[e + 1] += tetsOfEdgeStart[e];
  std::vector<int64_t> tetsOfEdge(tetsOfEdgeStart.back());
  {
    std::vector<int64_t> fill(tetsOfEdgeStart.begin(), tetsOfEdgeStart.end() - 1);
    for (size_t t = 0; t < edgesOfTet.size(); ++t)
      for (int64_t e : edgesOfTet[t]) tetsOfEdge[fill[e]++] = static_cast<int64_t>(t);
  }

  // Classify edges before any point moves.
  std::unordered_map<EdgeKey, int, EdgeHash> curveOfFeatureEdge;
  for (size_t i = 0; i < mesh.feature_edges.size(); ++i)
    curveOfFeatureEdge[edgeKey(mesh.feature_edges[i][0], mesh.feature_edges[i][1])] =
        mesh.feature_edge_curves.empty() ? -1 : mesh.feature_edge_curves[i];
  std::unordered_map<EdgeKey, char, EdgeHash> boundaryEdges;
  {
    const std::vector<BoundaryTriangle> derived = mesh.boundary.empty() ? extractBoundary(mesh) : std::vector<BoundaryTriangle>{};
    const std::vector<BoundaryTriangle>& boundary = mesh.boundary.empty() ? derived : mesh.boundary;
    for (const BoundaryTriangle& tri : boundary)
      for (int k = 0; k < 3; ++k) boundaryEdges.emplace(edgeKey(tri.v[k], tri.v[(k + 1) % 3]), 1);
  }

  // Mid nodes start straight, so every tet starts out as valid as its corners make it.
  const int64_t firstMidNode = static_cast<int64_t>(mesh.points.size());
  const bool hasDimensions = !mesh.vertex_dimension.empty();
  const bool hasCurves = !mesh.vertex_curve.empty();
  const bool hasBoundaryEntries = !mesh.vertex_boundary_entry.empty();
  mesh.points.reserve(mesh.points.size() + edges.size());
  for (const EdgeKey& e : edges) {
    mesh.points.push_back(0.5 * (mesh.points[e[0]] + mesh.points[e[1]]));
    auto feature = curveOfFeatureEdge.find(e);
    if (hasDimensions)
      mesh.vertex_dimension.push_back(feature != curveOfFeatureEdge.end() ? 1 : boundaryEdges.count(e) ? 2 : 3);
    if (hasCurves) mesh.vertex_curve.push_back(feature != curveOfFeatureEdge.end() ? feature->second : -1);
    if (hasBoundaryEntries) mesh.vertex_boundary_entry.push_back(-1);  // placed by the caller, on what it knows
  }
  mesh.tet_mid_nodes.resize(mesh.tets.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int e = 0; e < 6; ++e) mesh.tet_mid_nodes[t][e] = firstMidNode + edgesOfTet[t][e];

  // Place one edge at a time and re-check the tets around it with the mid nodes placed so
  // far: each accepted move keeps every tet valid, so the final mesh is valid wherever its
  // straight-sided version was.
  // An edge refused in one pass may fit once its neighbours have curved too (a thin tet
  // hugging a curved face only stays valid when all its edges follow the face), so refused
  // edges get further passes while they make progress.
  std::vector<size_t> pending(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) pending[e] = e;
  for (int pass = 0; pass < 4 && !pending.empty(); ++pass) {
    std::vector<size_t> refused;
    for (size_t e : pending) {
      const int64_t midNode = firstMidNode + static_cast<int64_t>(e);
      const Point3 straight = 0.5 * (mesh.points[edges[e][0]] + mesh.points[edges[e][1]]);
      const Point3 placed = place(edges[e][0], edges[e][1], straight);
      if (placed == straight) continue;
      bool valid = isFinite(placed);
      if (valid) {
        mesh.points[midNode] = placed;
        for (int64_t i = tetsOfEdgeStart[e]; i < tetsOfEdgeStart[e + 1] && valid; ++i) {
          const auto t = static_cast<size_t>(tetsOfEdge[i]);
          valid = curvedTetIsValid(mesh, t);
        }
      }
      if (!valid) {
        mesh.points[midNode] = straight;
        refused.push_back(e);
      }
    }
    if (refused.size() == pending.size()) break;  // no progress
    pending = std::move(refused);
  }
  return static_cast<int>(pending.size());
}

bool curvedTetIsValid(const TetMesh& mesh, size_t t) {
  const auto& v = mesh.tets[t];
  const double straightJacobian =
      6.0 * tetVolume(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]);
  const double smallest = tet10MinJacobianAtCornersAndGaussPoints(tet10Nodes(mesh, t));
  return straightJacobian > 0 && smallest > 0 && smallest >= kMinJacobianFraction * straightJacobian;
}

int curveStraightFeatureMidNodes(TetMesh& mesh, const MidNodePlacer& onCurve) {
  if (mesh.order() != 2) return 0;
  std::unordered_map<EdgeKey, char, EdgeHash> featureEdges;
  for (const auto& fe : mesh.feature_edges) featureEdges.emplace(edgeKey(fe[0], fe[1]), 1);
  // Feature mid nodes still straight, with the tets they belong to.
  std::unordered_map<int64_t, std::vector<size_t>> tetsOfMidNode;
  std::vector<std::pair<int64_t, EdgeKey>> straight;  // mid node, its edge; in first-met order
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int e = 0; e < 6; ++e) {
      const EdgeKey key = edgeKey(mesh.tets[t][kTetEdgeCorners[e][0]], mesh.tets[t][kTetEdgeCorners[e][1]]);
      if (!featureEdges.count(key)) continue;
      const int64_t mid = mesh.tet_mid_nodes[t][e];
      auto [it, added] = tetsOfMidNode.emplace(mid, std::vector<size_t>{});
      it->second.push_back(t);
      if (added) straight.push_back({mid, key});
    }
  int curved = 0;
  for (const auto& [mid, key] : straight) {
    const Point3 a = mesh.points[key[0]], b = mesh.points[key[1]];
    const Point3 middle = 0.5 * (a + b);
    if (mesh.points[mid] != middle) continue;  // curved by makeSecondOrder
    const Point3 onArc = onCurve(key[0], key[1], middle);
    if (!isFinite(onArc) || onArc == middle) continue;  // no curve, or a straight one
    bool placed = false;
    for (double offset : {0.05, 0.1, 0.15, 0.2}) {
      for (double fraction : {0.5 + offset, 0.5 - offset}) {
        const Point3 candidate = onCurve(key[0], key[1], a + fraction * (b - a));
        if (!isFinite(candidate)) continue;
        mesh.points[mid] = candidate;
        placed = true;
        for (size_t t : tetsOfMidNode[mid]) placed = placed && curvedTetIsValid(mesh, t);
        if (placed) break;
      }
      if (placed) break;
    }
    if (placed)
      ++curved;
    else
      mesh.points[mid] = middle;
  }
  return curved;
}

int64_t makeSecondOrderOnGeometry(TetMesh& mesh, const HierarchicalOracle& oracle, const CurveRegistry& curves,
                                  const std::vector<int>& vertexEntry) {
  std::unordered_map<EdgeKey, int, EdgeHash> featureCurveOfEdge;
  for (size_t i = 0; i < mesh.feature_edges.size(); ++i)
    featureCurveOfEdge[edgeKey(mesh.feature_edges[i][0], mesh.feature_edges[i][1])] = mesh.feature_edge_curves[i];
  std::unordered_set<EdgeKey, EdgeHash> boundaryEdges;
  for (const BoundaryTriangle& t : mesh.boundary)
    for (int k = 0; k < 3; ++k) boundaryEdges.insert(edgeKey(t.v[k], t.v[(k + 1) % 3]));
  // Mid nodes of curved edges and faces go onto the exact CAD geometry, the rest stay straight.
  auto place = [&](int64_t a, int64_t b, const Point3& mid) -> Point3 {
    const EdgeKey key = edgeKey(a, b);
    auto f = featureCurveOfEdge.find(key);
    if (f != featureCurveOfEdge.end()) {
      const BoundaryProjection q = curves.project(f->second, mid);
      if (std::isfinite(q.distance)) return q.point;
    }
    if (!boundaryEdges.count(key)) return mid;
    const int ea = vertexEntry[a], eb = vertexEntry[b];
    const BoundaryProjection q = (ea >= 0 && ea == eb) ? oracle.entries()[ea].source->project(mid)
                                                        : oracle.projectOnBoundary(mid);
    return std::isfinite(q.distance) ? q.point : mid;
  };
  int64_t straightMidNodes = makeSecondOrder(mesh, place);
  straightMidNodes -= curveStraightFeatureMidNodes(mesh, [&](int64_t a, int64_t b, const Point3& p) -> Point3 {
    auto f = featureCurveOfEdge.find(edgeKey(a, b));
    const BoundaryProjection q = f != featureCurveOfEdge.end() ? curves.project(f->second, p) : BoundaryProjection{};
    return std::isfinite(q.distance) ? q.point : Point3{NAN, NAN, NAN};
  });
  return straightMidNodes;
}

}  // namespace oraclemesh
