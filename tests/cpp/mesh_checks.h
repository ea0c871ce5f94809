#pragma once
// Checks that tests apply to any TetMesh, written independently of src/core/mesh/ so that a
// bug there cannot hide itself from the tests.
#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <vector>

#include "mesh/TetMesh.h"

namespace oraclemesh::test {

// Corner pairs of the six tet edges, in TetMesh's mid-node order 01, 12, 20, 03, 13, 23.
inline constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

// det of the isoparametric map's Jacobian at barycentric (l0..l3), for tet4 or tet10.
inline double jacobianDeterminant(const TetMesh& m, size_t t, const std::array<double, 4>& l) {
  static const double dL[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double J[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  auto add = [&](const Point3& x, const double grad[3]) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) J[r][c] += x[r] * grad[c];
  };
  const bool quadratic = m.order() == 2;
  for (int i = 0; i < 4; ++i) {
    const double s = quadratic ? 4 * l[i] - 1 : 1;
    const double g[3] = {s * dL[i][0], s * dL[i][1], s * dL[i][2]};
    add(m.points[m.tets[t][i]], g);
  }
  if (quadratic)
    for (int k = 0; k < 6; ++k) {
      const int i = kTetEdges[k][0], j = kTetEdges[k][1];
      const double g[3] = {4 * (l[i] * dL[j][0] + l[j] * dL[i][0]), 4 * (l[i] * dL[j][1] + l[j] * dL[i][1]),
                           4 * (l[i] * dL[j][2] + l[j] * dL[i][2])};
      add(m.points[m.tet_mid_nodes[t][k]], g);
    }
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

// Exact volume of a tet4 or tet10: det J is cubic, integrated exactly by a 3x3x3 Gauss rule
// on the cube mapped onto the reference tet (Duffy), whose own Jacobian adds degree 3.
inline double tetVolume(const TetMesh& m, size_t t) {
  static const double x[3] = {0.1127016653792583, 0.5, 0.8872983346207417};
  static const double w[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
  double v = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c) {
        const double u = x[a], s = x[b], r = x[c];
        const double xi = u, eta = s * (1 - u), zeta = r * (1 - u) * (1 - s);
        const double duffy = (1 - u) * (1 - u) * (1 - s);
        v += w[a] * w[b] * w[c] * duffy * jacobianDeterminant(m, t, {1 - xi - eta - zeta, xi, eta, zeta});
      }
  return v;
}

inline std::map<int, double> volumePerMaterial(const TetMesh& m) {
  std::map<int, double> v;
  for (size_t t = 0; t < m.tets.size(); ++t) v[m.tet_materials[t]] += tetVolume(m, t);
  return v;
}

using Face = std::array<int64_t, 3>;

inline Face sortedFace(int64_t a, int64_t b, int64_t c) {
  Face f{a, b, c};
  std::sort(f.begin(), f.end());
  return f;
}

// Faces of the material boundary (between different materials, or on the outside).
inline std::vector<Face> boundaryFaces(const TetMesh& m, std::map<Face, std::vector<int>>* owners = nullptr) {
  std::map<Face, std::vector<int>> faces;
  static const int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (const auto& f : kFaces)
      faces[sortedFace(m.tets[t][f[0]], m.tets[t][f[1]], m.tets[t][f[2]])].push_back(m.tet_materials[t]);
  std::vector<Face> boundary;
  for (const auto& [face, materials] : faces)
    if (materials.size() == 1 || (materials.size() == 2 && materials[0] != materials[1])) boundary.push_back(face);
  if (owners) *owners = std::move(faces);
  return boundary;
}

// mesh.boundary as sorted faces, in boundaryFaces' order: equal to it when the list is the
// boundary of the tets (phases that change boundary triangles must rebuild the list).
inline std::vector<Face> listedBoundaryFaces(const TetMesh& m) {
  std::vector<Face> listed;
  for (const BoundaryTriangle& b : m.boundary) listed.push_back(sortedFace(b.v[0], b.v[1], b.v[2]));
  std::sort(listed.begin(), listed.end());
  return listed;
}

inline std::map<std::pair<int64_t, int64_t>, int64_t> midNodeOfEdge(const TetMesh& m) {
  std::map<std::pair<int64_t, int64_t>, int64_t> mid;
  for (size_t t = 0; t < m.tet_mid_nodes.size(); ++t)
    for (int k = 0; k < 6; ++k) {
      int64_t a = m.tets[t][kTetEdges[k][0]], b = m.tets[t][kTetEdges[k][1]];
      mid[{std::min(a, b), std::max(a, b)}] = m.tet_mid_nodes[t][k];
    }
  return mid;
}

// Corner and (tet10) mid nodes of the material boundary.
inline std::set<int64_t> boundaryNodes(const TetMesh& m) {
  std::set<int64_t> nodes;
  const auto mids = midNodeOfEdge(m);
  for (const Face& f : boundaryFaces(m)) {
    nodes.insert(f.begin(), f.end());
    for (int k = 0; k < 3; ++k) {
      const int64_t a = f[k], b = f[(k + 1) % 3];
      auto it = mids.find({std::min(a, b), std::max(a, b)});
      if (it != mids.end()) nodes.insert(it->second);
    }
  }
  return nodes;
}

// Whether u and v are corners of one tet.
inline bool hasTetEdge(const TetMesh& m, int64_t u, int64_t v) {
  for (const auto& t : m.tets)
    if (std::count(t.begin(), t.end(), u) && std::count(t.begin(), t.end(), v)) return true;
  return false;
}

// Feature edges that are no edge of any tet (FreeCAD's hand-off looks each one up among
// the tets' edges); independent of the core's own count.
inline int64_t featureEdgesNotTetEdges(const TetMesh& m) {
  std::set<std::pair<int64_t, int64_t>> edges;
  for (const auto& t : m.tets)
    for (const auto& e : kTetEdges) edges.insert(std::minmax(t[e[0]], t[e[1]]));
  int64_t missing = 0;
  for (const auto& [a, b] : m.feature_edges) missing += edges.count(std::minmax(a, b)) == 0;
  return missing;
}

struct Conformity {
  int64_t faces_shared_by_more_than_two = 0;
  int64_t open_boundary_edges = 0;  // edges in an odd number of one material's boundary faces
  int64_t inverted = 0;             // det J <= 0 at a corner or the centroid
  int64_t mid_nodes_not_shared = 0;
};

inline Conformity conformity(const TetMesh& m) {
  Conformity c;
  std::map<Face, std::vector<int>> owners;
  boundaryFaces(m, &owners);
  for (const auto& [face, materials] : owners)
    if (materials.size() > 2) ++c.faces_shared_by_more_than_two;
  // The boundary of each material's region must be closed: every edge in an even number of
  // its faces. (Over all materials together, junction edges have three faces.)
  std::map<int, std::map<std::pair<int64_t, int64_t>, int>> edgeUse;
  for (const auto& [face, materials] : owners)
    for (int material : materials) {
      if (std::count(materials.begin(), materials.end(), material) != 1) continue;
      for (int k = 0; k < 3; ++k)
        ++edgeUse[material][{std::min(face[k], face[(k + 1) % 3]), std::max(face[k], face[(k + 1) % 3])}];
    }
  for (const auto& [material, edges] : edgeUse)
    for (const auto& [edge, n] : edges)
      if (n % 2 != 0) ++c.open_boundary_edges;
  const std::array<std::array<double, 4>, 5> samples{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1},
                                                       {0.25, 0.25, 0.25, 0.25}}};
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (const auto& l : samples)
      if (jacobianDeterminant(m, t, l) <= 0) {
        ++c.inverted;
        break;
      }
  if (m.order() == 2) {
    std::map<std::pair<int64_t, int64_t>, std::set<int64_t>> mids;
    for (size_t t = 0; t < m.tets.size(); ++t)
      for (int k = 0; k < 6; ++k) {
        int64_t a = m.tets[t][kTetEdges[k][0]], b = m.tets[t][kTetEdges[k][1]];
        mids[{std::min(a, b), std::max(a, b)}].insert(m.tet_mid_nodes[t][k]);
      }
    for (const auto& [edge, nodes] : mids)
      if (nodes.size() != 1) ++c.mid_nodes_not_shared;
  }
  return c;
}

}  // namespace oraclemesh::test
