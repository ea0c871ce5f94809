#include "mesh/Topology.h"

#include <algorithm>
#include <array>
#include <map>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "Error.h"
#include "mesh/Quality.h"

namespace oraclemesh {

namespace {

// Faces opposite corner 0, 1, 2, 3, ordered so that the normal points out of a positively
// oriented tet.
constexpr int kOutwardFaceOpposite[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

uint64_t mixBits(uint64_t x) {  // splitmix64 finalizer: spreads consecutive indices apart
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

template <size_t N>
struct IndexTupleHash {
  size_t operator()(const std::array<int64_t, N>& key) const {
    uint64_t h = 0;
    for (int64_t k : key) h = mixBits(h ^ static_cast<uint64_t>(k));
    return static_cast<size_t>(h);
  }
};

using FaceKey = std::array<int64_t, 3>;  // sorted vertex indices

// One tet face and the (at most two, in a valid mesh) tets that have it.
struct FaceRecord {
  int64_t tets[2] = {-1, -1};
  int local_face[2] = {-1, -1};  // which corner of the tet the face is opposite to
  int tet_count = 0;
};

// Faces in the order their first tet (in tets order) meets them, so results built from this
// table are deterministic. The faces are bucketed by their smallest vertex (a vertex starts
// few faces, about 20 here) and matched inside the bucket: the same table as a hash map of
// sorted vertex triples gives, at a fraction of its cost (the map was the largest single
// item of extracting a thesis-engine mesh). Callers have checked the indices
// (requireConsistentIndices).
std::vector<FaceRecord> buildFaceTable(const TetMesh& mesh) {
  const size_t occurrences = mesh.tets.size() * 4;
  std::vector<FaceKey> keyOf(occurrences);
  int64_t vertexEnd = 0;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const auto& f = kOutwardFaceOpposite[k];
      FaceKey key{mesh.tets[t][f[0]], mesh.tets[t][f[1]], mesh.tets[t][f[2]]};
      std::sort(key.begin(), key.end());
      vertexEnd = std::max(vertexEnd, key[2] + 1);
      keyOf[t * 4 + k] = key;
    }
  // Occurrences grouped by smallest vertex, each group in (tet, corner) order.
  std::vector<size_t> bucketStart(static_cast<size_t>(vertexEnd) + 1, 0);
  for (const FaceKey& key : keyOf) ++bucketStart[static_cast<size_t>(key[0]) + 1];
  for (size_t v = 1; v < bucketStart.size(); ++v) bucketStart[v] += bucketStart[v - 1];
  std::vector<size_t> bucket(occurrences);
  {
    std::vector<size_t> fill(bucketStart.begin(), bucketStart.end() - 1);
    for (size_t o = 0; o < occurrences; ++o) bucket[fill[static_cast<size_t>(keyOf[o][0])]++] = o;
  }
  std::vector<FaceRecord> faces;
  faces.reserve(mesh.tets.size() * 2 + 16);
  std::vector<int64_t> faceOf(occurrences, -1);
  for (size_t o = 0; o < occurrences; ++o) {
    const FaceKey& key = keyOf[o];
    const size_t v = static_cast<size_t>(key[0]);
    // The first occurrence of this face in tets order names it.
    size_t first = o;
    for (size_t i = bucketStart[v]; i < bucketStart[v + 1] && bucket[i] < o; ++i)
      if (keyOf[bucket[i]] == key) {
        first = bucket[i];
        break;
      }
    if (first == o) {
      faceOf[o] = static_cast<int64_t>(faces.size());
      faces.emplace_back();
    } else {
      faceOf[o] = faceOf[first];
    }
    FaceRecord& record = faces[faceOf[o]];
    if (record.tet_count < 2) {
      record.tets[record.tet_count] = static_cast<int64_t>(o / 4);
      record.local_face[record.tet_count] = static_cast<int>(o % 4);
    }
    ++record.tet_count;
  }
  return faces;
}

BoundaryTriangle triangleOf(const TetMesh& mesh, int64_t tet, int localFace, int materialOut) {
  const auto& f = kOutwardFaceOpposite[localFace];
  BoundaryTriangle tri;
  tri.v = {mesh.tets[tet][f[0]], mesh.tets[tet][f[1]], mesh.tets[tet][f[2]]};
  tri.material_in = mesh.tet_materials[tet];
  tri.material_out = materialOut;
  return tri;
}

void requireIndex(int64_t index, size_t count, const char* what, size_t owner) {
  if (index < 0 || static_cast<uint64_t>(index) >= count)
    throw Error("internal error: " + std::string(what) + " " + std::to_string(owner) + " refers to point " +
                std::to_string(index) + " but the mesh has " + std::to_string(count) +
                " points; please report this with the job file");
}

void requireLength(size_t length, size_t expected, const char* what, bool emptyAllowed) {
  if (length == expected || (emptyAllowed && length == 0)) return;
  throw Error("internal error: the mesh has " + std::to_string(length) + " " + what + " where " +
              std::to_string(expected) + " are expected; please report this with the job file");
}

}  // namespace

void requireConsistentIndices(const TetMesh& mesh) {
  const size_t n = mesh.points.size();
  requireLength(mesh.tet_materials.size(), mesh.tets.size(), "tet material ids", false);
  requireLength(mesh.tet_mid_nodes.size(), mesh.tets.size(), "tet mid-node rows", true);
  requireLength(mesh.feature_edge_curves.size(), mesh.feature_edges.size(), "feature edge curve ids", true);
  requireLength(mesh.vertex_dimension.size(), n, "vertex dimensions", true);
  requireLength(mesh.vertex_curve.size(), n, "vertex curve ids", true);
  requireLength(mesh.vertex_boundary_entry.size(), n, "vertex boundary entries", true);
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    for (int64_t v : mesh.tets[t]) requireIndex(v, n, "tet", t);
    if (!mesh.tet_mid_nodes.empty())
      for (int64_t v : mesh.tet_mid_nodes[t]) requireIndex(v, n, "mid node of tet", t);
  }
  for (size_t i = 0; i < mesh.boundary.size(); ++i)
    for (int64_t v : mesh.boundary[i].v) requireIndex(v, n, "boundary triangle", i);
  for (size_t i = 0; i < mesh.feature_edges.size(); ++i)
    for (int64_t v : mesh.feature_edges[i]) requireIndex(v, n, "feature edge", i);
}

int64_t featureEdgesNotTetEdges(const TetMesh& mesh, size_t* first) {
  requireConsistentIndices(mesh);
  std::unordered_set<uint64_t> tetEdges;
  tetEdges.reserve(mesh.tets.size() * 7);
  for (const auto& t : mesh.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) tetEdges.insert(undirectedEdgeKey(t[a], t[b]));
  int64_t missing = 0;
  for (size_t i = 0; i < mesh.feature_edges.size(); ++i) {
    if (tetEdges.count(undirectedEdgeKey(mesh.feature_edges[i][0], mesh.feature_edges[i][1]))) continue;
    if (missing++ == 0 && first) *first = i;
  }
  return missing;
}

void requireFeatureEdgesInTets(const TetMesh& mesh) {
  size_t first = 0;
  const int64_t missing = featureEdgesNotTetEdges(mesh, &first);
  if (missing == 0) return;
  const Point3& a = mesh.points[mesh.feature_edges[first][0]];
  const Point3& b = mesh.points[mesh.feature_edges[first][1]];
  std::ostringstream message;
  message << "internal error: " << missing << " of " << mesh.feature_edges.size()
          << " feature edges (sharp, junction or polyline edges) are no edge of any tetrahedron, the first from ("
          << a[0] << ", " << a[1] << ", " << a[2] << ") to (" << b[0] << ", " << b[1] << ", " << b[2]
          << "): the mesh would not keep those edges; please report this with the job file (a smaller edge_size "
             "there, or the other engine, may avoid it)";
  throw Error(message.str());
}

namespace {

// Whether some three of `points` span a triangle (they do not all lie on one line).
bool spanATriangle(const TetMesh& mesh, const std::vector<int64_t>& points) {
  if (points.size() < 3) return false;
  const Point3& a = mesh.points[points[0]];
  size_t far = 1;
  for (size_t i = 2; i < points.size(); ++i)
    if (distance(a, mesh.points[points[i]]) > distance(a, mesh.points[points[far]])) far = i;
  const Point3 axis = mesh.points[points[far]] - a;
  const double length = norm(axis);
  if (length == 0) return false;
  for (int64_t p : points)
    if (norm(cross(axis, mesh.points[p] - a)) > 1e-9 * length * length) return true;
  return false;
}

}  // namespace

std::map<int, int64_t> componentsPerMaterial(const TetMesh& mesh) {
  requireConsistentIndices(mesh);
  std::vector<size_t> parent(mesh.tets.size());
  for (size_t t = 0; t < parent.size(); ++t) parent[t] = t;
  auto root = [&](size_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for (const FaceRecord& face : buildFaceTable(mesh)) {
    if (face.tet_count < 2) continue;
    const size_t a = static_cast<size_t>(face.tets[0]), b = static_cast<size_t>(face.tets[1]);
    if (mesh.tet_materials[a] == mesh.tet_materials[b]) parent[root(a)] = root(b);
  }
  // Pieces of one material that share three nodes not on one line hold each other rigidly: to
  // a solver they are one piece. A sliver in a cusp where two curves meet at 0 degrees has all
  // its faces on the boundary but every node shared; a piece hanging by an edge or a node stays
  // apart. Merging two pieces can give the merged one such nodes with a third: repeat.
  for (bool merged = true; merged;) {
    merged = false;
    // Most nodes lie in one piece: list the pieces only at nodes where a second one shows.
    constexpr size_t kNone = static_cast<size_t>(-1);
    std::vector<size_t> firstPiece(mesh.points.size(), kNone);
    std::unordered_map<int64_t, std::vector<size_t>> piecesAt;
    for (size_t t = 0; t < mesh.tets.size(); ++t)
      for (int64_t v : mesh.tets[t]) {
        const size_t r = root(t);
        if (firstPiece[v] == kNone) firstPiece[v] = r;
        if (firstPiece[v] == r) continue;
        std::vector<size_t>& at = piecesAt[v];
        if (at.empty()) at.push_back(firstPiece[v]);
        if (std::find(at.begin(), at.end(), r) == at.end()) at.push_back(r);
      }
    std::map<std::pair<size_t, size_t>, std::vector<int64_t>> shared;
    for (const auto& [v, at] : piecesAt) {
      for (size_t i = 0; i < at.size(); ++i)
        for (size_t j = i + 1; j < at.size(); ++j)
          if (mesh.tet_materials[at[i]] == mesh.tet_materials[at[j]])
            shared[std::minmax(at[i], at[j])].push_back(v);
    }
    for (const auto& [pieces, points] : shared)
      if (root(pieces.first) != root(pieces.second) && spanATriangle(mesh, points)) {
        parent[root(pieces.first)] = root(pieces.second);
        merged = true;
      }
  }
  std::map<int, int64_t> components;
  for (size_t t = 0; t < parent.size(); ++t)
    if (root(t) == t) ++components[mesh.tet_materials[t]];
  return components;
}

std::vector<BoundaryFace> boundaryElementFaces(const TetMesh& mesh) {
  requireConsistentIndices(mesh);
  std::vector<BoundaryFace> boundary;
  for (const FaceRecord& face : buildFaceTable(mesh)) {
    if (face.tet_count == 1) {
      boundary.push_back({face.tets[0], face.local_face[0], 0, -1, -1});
    } else if (face.tet_count == 2) {
      const int m0 = mesh.tet_materials[face.tets[0]], m1 = mesh.tet_materials[face.tets[1]];
      if (m0 == m1) continue;
      const int side = m0 < m1 ? 0 : 1;  // the smaller material id is the inside
      boundary.push_back({face.tets[side], face.local_face[side], std::max(m0, m1), face.tets[1 - side],
                          face.local_face[1 - side]});
    }
  }
  return boundary;
}

std::vector<BoundaryTriangle> extractBoundary(const TetMesh& mesh) {
  std::vector<BoundaryTriangle> boundary;
  for (const BoundaryFace& face : boundaryElementFaces(mesh))
    boundary.push_back(triangleOf(mesh, face.tet, face.opposite_corner, face.material_out));
  return boundary;
}

ConformityReport checkConformity(const TetMesh& mesh) {
  requireConsistentIndices(mesh);
  ConformityReport report;

  // Each material's region must be closed: every edge of its boundary faces is used an even
  // number of times by them (twice on a manifold edge, four times where two parts of the
  // region touch along an edge).
  std::unordered_map<std::array<int64_t, 3>, int64_t, IndexTupleHash<3>> edgeUseByMaterial;
  auto addFaceEdges = [&](int material, int64_t tet, int localFace) {
    const auto& f = kOutwardFaceOpposite[localFace];
    for (int k = 0; k < 3; ++k) {
      int64_t a = mesh.tets[tet][f[k]], b = mesh.tets[tet][f[(k + 1) % 3]];
      if (a > b) std::swap(a, b);
      ++edgeUseByMaterial[{static_cast<int64_t>(material), a, b}];
    }
  };
  for (const FaceRecord& face : buildFaceTable(mesh)) {
    if (face.tet_count > 2) {
      ++report.faces_shared_by_more_than_two;
      continue;
    }
    if (face.tet_count == 1) {
      addFaceEdges(mesh.tet_materials[face.tets[0]], face.tets[0], face.local_face[0]);
    } else if (mesh.tet_materials[face.tets[0]] != mesh.tet_materials[face.tets[1]]) {
      for (int side = 0; side < 2; ++side)
        addFaceEdges(mesh.tet_materials[face.tets[side]], face.tets[side], face.local_face[side]);
    }
  }
  for (const auto& [edge, uses] : edgeUseByMaterial)
    if (uses % 2 != 0) ++report.open_boundary_edges;

  const bool quadratic = mesh.order() == 2;
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    bool inverted = tetVolume(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]) <= 0;
    if (!inverted && quadratic) inverted = tet10MinJacobianAtCornersAndGaussPoints(tet10Nodes(mesh, t)) <= 0;
    if (inverted) ++report.inverted_tets;
  }

  std::vector<char> used(mesh.points.size(), 0);
  for (const auto& tet : mesh.tets)
    for (int64_t v : tet) used[v] = 1;

  if (quadratic) {
    // Each mid node must belong to exactly one edge and each edge must have one mid node;
    // a disagreement means two neighbours are not connected along that edge.
    std::unordered_map<std::array<int64_t, 2>, int64_t, IndexTupleHash<2>> midNodeOfEdge;
    std::unordered_map<int64_t, std::array<int64_t, 2>> edgeOfMidNode;
    std::unordered_map<std::array<int64_t, 2>, char, IndexTupleHash<2>> edgeAlreadyCounted;
    std::vector<char> isCorner = used;
    for (size_t t = 0; t < mesh.tets.size(); ++t)
      for (int e = 0; e < 6; ++e) {
        int64_t a = mesh.tets[t][kTetEdgeCorners[e][0]], b = mesh.tets[t][kTetEdgeCorners[e][1]];
        if (a > b) std::swap(a, b);
        const std::array<int64_t, 2> edge{a, b};
        const int64_t mid = mesh.tet_mid_nodes[t][e];
        used[mid] = 1;
        bool consistent = !isCorner[mid];
        auto [edgeIt, newEdge] = midNodeOfEdge.emplace(edge, mid);
        if (!newEdge && edgeIt->second != mid) consistent = false;
        auto [midIt, newMid] = edgeOfMidNode.emplace(mid, edge);
        if (!newMid && midIt->second != edge) consistent = false;
        // Count each offending edge once, however many of its tets disagree.
        if (!consistent && edgeAlreadyCounted.emplace(edge, 1).second) ++report.inconsistent_mid_nodes;
      }
  }
  report.unused_points = std::count(used.begin(), used.end(), 0);
  return report;
}

}  // namespace oraclemesh
