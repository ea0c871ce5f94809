#include "mesh/InterfaceSplit.h"

#include <algorithm>
#include <map>
#include <unordered_map>
#include <vector>

#include "mesh/Quality.h"
#include "mesh/Topology.h"

namespace oraclemesh {

namespace {

// Appends a copy of point v with its per-vertex data; returns its index.
int64_t copyPoint(TetMesh& mesh, int64_t v) {
  mesh.points.push_back(mesh.points[v]);
  if (!mesh.vertex_dimension.empty()) mesh.vertex_dimension.push_back(mesh.vertex_dimension[v]);
  if (!mesh.vertex_curve.empty()) mesh.vertex_curve.push_back(mesh.vertex_curve[v]);
  if (!mesh.vertex_boundary_entry.empty()) mesh.vertex_boundary_entry.push_back(mesh.vertex_boundary_entry[v]);
  return static_cast<int64_t>(mesh.points.size()) - 1;
}

// Tets having each point as a corner, in tet order.
std::vector<std::vector<int64_t>> cornerIncidence(const TetMesh& mesh) {
  std::vector<std::vector<int64_t>> tetsAt(mesh.points.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int64_t v : mesh.tets[t]) tetsAt[v].push_back(static_cast<int64_t>(t));
  return tetsAt;
}

}  // namespace

InterfaceSplitStats splitInterfaces(TetMesh& mesh, const InterfacePlan& plan) {
  requireConsistentIndices(mesh);
  InterfaceSplitStats stats;
  if (!plan.splitsAny()) return stats;

  const size_t originalPoints = mesh.points.size();
  const std::vector<std::vector<int64_t>> tetsAt = cornerIncidence(mesh);
  // (original corner, material) -> the corner that material's tets use, for split corners only.
  std::map<std::pair<int64_t, int>, int64_t> cornerFor;

  for (size_t v = 0; v < originalPoints; ++v) {
    const std::vector<int64_t>& around = tetsAt[v];
    if (around.empty()) continue;
    std::vector<int> materials;
    for (int64_t t : around) materials.push_back(mesh.tet_materials[t]);
    std::sort(materials.begin(), materials.end());
    materials.erase(std::unique(materials.begin(), materials.end()), materials.end());
    if (materials.size() < 2) continue;
    // Union-find over the materials at this node, joined by their bonded pairs.
    std::vector<size_t> parent(materials.size());
    for (size_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto root = [&](size_t i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    for (size_t i = 0; i < materials.size(); ++i)
      for (size_t j = i + 1; j < materials.size(); ++j)
        if (plan.bonded(materials[i], materials[j])) {
          const size_t a = root(i), b = root(j);
          parent[std::max(a, b)] = std::min(a, b);  // the smaller index is the root: class order = material order
        }
    for (size_t i = 0; i < materials.size(); ++i)
      for (size_t j = i + 1; j < materials.size(); ++j) {
        if (root(i) != root(j) || plan.bonded(materials[i], materials[j])) continue;
        KeptJoined& kept = stats.kept_joined[{materials[i], materials[j]}];
        ++kept.nodes;
        for (size_t k = 0; k < materials.size(); ++k)
          if (k != i && k != j && root(k) == root(i)) kept.through.insert(materials[k]);
      }
    // Class roots in material order; root 0 (the smallest material's class) keeps v.
    std::map<size_t, int64_t> nodeOfClass;
    for (size_t i = 0; i < materials.size(); ++i) {
      const size_t r = root(i);
      if (nodeOfClass.count(r)) continue;
      if (r == root(0)) {
        nodeOfClass[r] = static_cast<int64_t>(v);
      } else {
        nodeOfClass[r] = copyPoint(mesh, static_cast<int64_t>(v));
        ++stats.corner_copies;
      }
    }
    if (nodeOfClass.size() < 2) continue;
    for (size_t i = 0; i < materials.size(); ++i)
      cornerFor[{static_cast<int64_t>(v), materials[i]}] = nodeOfClass[root(i)];
    for (int64_t t : around) {
      const int64_t to = cornerFor[{static_cast<int64_t>(v), mesh.tet_materials[t]}];
      if (to == static_cast<int64_t>(v)) continue;
      for (int64_t& corner : mesh.tets[t])
        if (corner == static_cast<int64_t>(v)) corner = to;
    }
  }
  if (cornerFor.empty()) return stats;

  if (mesh.order() == 2) {
    // Per mid node, the tets' new edges in order of first use; each further edge gets a copy.
    std::unordered_map<int64_t, std::vector<std::pair<uint64_t, int64_t>>> edgesOfMid;  // mid -> (edge, node)
    for (size_t t = 0; t < mesh.tets.size(); ++t)
      for (int e = 0; e < 6; ++e) {
        int64_t& mid = mesh.tet_mid_nodes[t][e];
        const uint64_t edge =
            undirectedEdgeKey(mesh.tets[t][kTetEdgeCorners[e][0]], mesh.tets[t][kTetEdgeCorners[e][1]]);
        auto& seen = edgesOfMid[mid];
        auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& s) { return s.first == edge; });
        if (it == seen.end()) {
          seen.push_back({edge, seen.empty() ? mid : copyPoint(mesh, mid)});
          if (seen.size() > 1) ++stats.mid_copies;
          it = seen.end() - 1;
        }
        mid = it->second;
      }
  }

  auto sideCorner = [&](int64_t v, int material) {
    const auto it = cornerFor.find({v, material});
    return it != cornerFor.end() ? it->second : v;
  };
  for (BoundaryTriangle& tri : mesh.boundary)
    for (int64_t& v : tri.v) v = sideCorner(v, tri.material_in);

  // Feature edges: one per distinct new edge among the tets that had the original one.
  const size_t featureCount = mesh.feature_edges.size();
  for (size_t i = 0; i < featureCount; ++i) {
    const int64_t a = mesh.feature_edges[i][0], b = mesh.feature_edges[i][1];
    if (a >= static_cast<int64_t>(originalPoints) || b >= static_cast<int64_t>(originalPoints)) continue;
    std::vector<std::array<int64_t, 2>> ends;
    const std::vector<int64_t>& atA = tetsAt[a];
    const std::vector<int64_t>& atB = tetsAt[b];
    for (int64_t t : atA) {
      if (!std::binary_search(atB.begin(), atB.end(), t)) continue;
      const std::array<int64_t, 2> e = {sideCorner(a, mesh.tet_materials[t]), sideCorner(b, mesh.tet_materials[t])};
      if (std::find(ends.begin(), ends.end(), e) == ends.end()) ends.push_back(e);
    }
    if (ends.empty()) continue;  // not a tet edge; requireFeatureEdgesInTets reports it
    mesh.feature_edges[i] = ends[0];
    for (size_t k = 1; k < ends.size(); ++k) {
      mesh.feature_edges.push_back(ends[k]);
      if (!mesh.feature_edge_curves.empty()) mesh.feature_edge_curves.push_back(mesh.feature_edge_curves[i]);
    }
  }
  return stats;
}

}  // namespace oraclemesh
