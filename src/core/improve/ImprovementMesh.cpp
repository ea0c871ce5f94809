#include "improve/ImprovementMesh.h"

#include <algorithm>
#include <cmath>

#include "Error.h"
#include "mesh/Quality.h"

namespace oraclemesh {
namespace {

// Relative tolerance for "in the plane" and "on the line": the boundary snap puts vertices on
// planar faces and straight edges to rounding, far inside it; a curved face sampled at any
// usable density is far outside it.
constexpr double kFlatTolerance = 1e-9;

}  // namespace

std::array<int64_t, 3> ImprovementMesh::faceKey(int64_t a, int64_t b, int64_t c) {
  std::array<int64_t, 3> k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

ImprovementMesh::ImprovementMesh(TetMesh& mesh, const BoundaryPlacement* placement, double curvedVolumeBound)
    : points_(mesh.points), placement_(placement), curved_volume_bound_(curvedVolumeBound) {
  if (mesh.order() != 1) throw Error("mesh improvement: second-order mesh; improve before placing mid nodes");
  tets_ = mesh.tets;
  materials_ = mesh.tet_materials;
  alive_.assign(tets_.size(), 1);
  vertex_tets_.resize(points_.size());
  for (size_t t = 0; t < tets_.size(); ++t)
    for (int64_t v : tets_[t]) vertex_tets_[v].push_back(static_cast<int64_t>(t));
  for (const BoundaryTriangle& b : mesh.boundary) protected_faces_.insert(faceKey(b.v[0], b.v[1], b.v[2]));
  for (const auto& e : mesh.feature_edges) protected_edges_.insert({std::min(e[0], e[1]), std::max(e[0], e[1]), -1});
  classifyVertices(mesh);
  changed_at_.assign(points_.size(), 0);
  if (placement_)
    for (size_t t = 0; t < tets_.size(); ++t) {
      const TetCorners& c = tets_[t];
      material_volume_[materials_[t]] += tetVolume(points_[c[0]], points_[c[1]], points_[c[2]], points_[c[3]]);
    }
}

bool ImprovementMesh::volumeFits(const std::map<int, double>& change) const {
  for (const auto& [material, dv] : change) {
    const auto total = material_volume_.find(material);
    if (total == material_volume_.end()) return false;
    const auto moved = volume_moved_.find(material);
    const double before = moved == volume_moved_.end() ? 0 : moved->second;
    if (before + std::abs(dv) > curved_volume_bound_ * std::abs(total->second)) return false;
  }
  return true;
}

void ImprovementMesh::spendVolume(const std::map<int, double>& change) {
  for (const auto& [material, dv] : change) volume_moved_[material] += std::abs(dv);
}

double ImprovementMesh::largestVolumeShareMoved() const {
  double share = 0;
  for (const auto& [material, moved] : volume_moved_) {
    const double total = std::abs(material_volume_.at(material));
    if (total > 0) share = std::max(share, moved / total);
  }
  return share;
}

void ImprovementMesh::markMoved(int64_t v) {
  ++clock_;
  for (int64_t t : vertex_tets_[v])
    for (int64_t w : tets_[t]) changed_at_[w] = clock_;
}

void ImprovementMesh::classifyVertices(const TetMesh& mesh) {
  const size_t n = points_.size();
  std::vector<std::vector<size_t>> boundaryOf(n), featureOf(n);
  for (size_t i = 0; i < mesh.boundary.size(); ++i)
    for (int64_t v : mesh.boundary[i].v) boundaryOf[v].push_back(i);
  for (size_t i = 0; i < mesh.feature_edges.size(); ++i)
    for (int64_t v : mesh.feature_edges[i]) featureOf[v].push_back(i);
  mobility_.assign(n, VertexMobility{});

  for (size_t v = 0; v < n; ++v) {
    const int dimension = v < mesh.vertex_dimension.size() ? mesh.vertex_dimension[v] : 3;
    if (dimension == 0 || vertex_tets_[v].empty()) continue;
    const Point3& p = points_[v];
    // Unit normals of the boundary triangles at v, all of one interface (one pair of materials).
    std::vector<Point3> normals;
    bool oneInterface = true;
    double reach = 0;
    for (size_t i : boundaryOf[v]) {
      const BoundaryTriangle& b = mesh.boundary[i];
      const BoundaryTriangle& first = mesh.boundary[boundaryOf[v].front()];
      const auto pair = std::minmax(b.material_in, b.material_out);
      if (pair != std::minmax(first.material_in, first.material_out)) oneInterface = false;
      const Point3 &a = points_[b.v[0]], &bb = points_[b.v[1]], &c = points_[b.v[2]];
      normals.push_back(unit(cross(bb - a, c - a)));
      for (int64_t w : b.v) reach = std::max(reach, distance(p, points_[w]));
    }
    if (featureOf[v].empty()) {
      if (boundaryOf[v].empty()) {
        if (dimension != 1) mobility_[v].freedom = VertexFreedom::Free;
        continue;
      }
      if (!oneInterface || dimension == 1) continue;
      // In a plane when every corner of its boundary triangles lies in the plane through v.
      Point3 sum{0, 0, 0};
      for (const Point3& m : normals) sum = sum + (dot(m, normals.front()) < 0 ? -1.0 : 1.0) * m;
      const Point3 axis = unit(sum);
      bool flat = norm(axis) > 0;
      for (size_t i : boundaryOf[v])
        for (int64_t w : mesh.boundary[i].v)
          if (std::abs(dot(points_[w] - p, axis)) > kFlatTolerance * reach) flat = false;
      if (!flat && !placement_) continue;
      mobility_[v].freedom = flat ? VertexFreedom::Planar : VertexFreedom::Curved;
      mobility_[v].axis = axis;
      for (size_t i : boundaryOf[v]) mobility_[v].boundary_triangles.push_back(mesh.boundary[i].v);
      continue;
    }
    if (featureOf[v].size() != 2) continue;
    const auto& e0 = mesh.feature_edges[featureOf[v][0]];
    const auto& e1 = mesh.feature_edges[featureOf[v][1]];
    if (!mesh.feature_edge_curves.empty() &&
        mesh.feature_edge_curves[featureOf[v][0]] != mesh.feature_edge_curves[featureOf[v][1]])
      continue;
    const int64_t w0 = e0[0] == static_cast<int64_t>(v) ? e0[1] : e0[0];
    const int64_t w1 = e1[0] == static_cast<int64_t>(v) ? e1[1] : e1[0];
    const Point3 u0 = points_[w0] - p, u1 = points_[w1] - p;
    if (dot(u0, u1) >= 0) continue;  // a curve doubling back at v: no chord to move along
    // Moving along the line keeps every boundary triangle at v in its plane only if the
    // line lies in that plane (then no material gains or loses volume).
    const Point3 axis = unit(u1 - u0);
    bool straight = norm(cross(u0, u1)) <= kFlatTolerance * norm(u0) * norm(u1);
    for (const Point3& m : normals)
      if (std::abs(dot(m, axis)) > kFlatTolerance) straight = false;
    if (!straight && !placement_) continue;
    mobility_[v].freedom = straight ? VertexFreedom::Linear : VertexFreedom::OnCurve;
    mobility_[v].axis = axis;
    mobility_[v].feature_neighbours = {w0, w1};
    if (!straight)
      for (size_t i : boundaryOf[v]) mobility_[v].boundary_triangles.push_back(mesh.boundary[i].v);
  }
}

std::vector<int64_t> ImprovementMesh::tetsAroundEdge(int64_t a, int64_t b) const {
  std::vector<int64_t> out;
  for (int64_t t : vertex_tets_[a]) {
    const TetCorners& c = tets_[t];
    if (c[0] == b || c[1] == b || c[2] == b || c[3] == b) out.push_back(t);
  }
  return out;
}

std::vector<int64_t> ImprovementMesh::tetsWithFace(int64_t a, int64_t b, int64_t c) const {
  std::vector<int64_t> out;
  for (int64_t t : tetsAroundEdge(a, b)) {
    const TetCorners& k = tets_[t];
    if (k[0] == c || k[1] == c || k[2] == c || k[3] == c) out.push_back(t);
  }
  return out;
}

bool ImprovementMesh::hasEdge(int64_t a, int64_t b) const {
  for (int64_t t : vertex_tets_[a]) {
    const TetCorners& c = tets_[t];
    if (c[0] == b || c[1] == b || c[2] == b || c[3] == b) return true;
  }
  return false;
}

bool ImprovementMesh::isProtectedEdge(int64_t a, int64_t b) const {
  return protected_edges_.count({std::min(a, b), std::max(a, b), -1}) > 0;
}

bool ImprovementMesh::isProtectedFace(int64_t a, int64_t b, int64_t c) const {
  return protected_faces_.count(faceKey(a, b, c)) > 0;
}

std::vector<int64_t> ImprovementMesh::replace(const std::vector<int64_t>& old, const std::vector<TetCorners>& made,
                                              int material) {
  ++clock_;
  for (int64_t t : old) {
    for (int64_t v : tets_[t]) changed_at_[v] = clock_;
    alive_[t] = 0;
    for (int64_t v : tets_[t]) {
      auto& list = vertex_tets_[v];
      list.erase(std::find(list.begin(), list.end(), t));
    }
  }
  std::vector<int64_t> added;
  for (const TetCorners& c : made) {
    const int64_t t = static_cast<int64_t>(tets_.size());
    tets_.push_back(c);
    materials_.push_back(material);
    alive_.push_back(1);
    for (int64_t v : c) vertex_tets_[v].push_back(t);
    added.push_back(t);
  }
  return added;
}

void ImprovementMesh::writeBack(TetMesh& mesh) const {
  mesh.tets.clear();
  mesh.tet_materials.clear();
  for (size_t t = 0; t < tets_.size(); ++t)
    if (alive_[t]) {
      mesh.tets.push_back(tets_[t]);
      mesh.tet_materials.push_back(materials_[t]);
    }
}

}  // namespace oraclemesh
