#include "improve/ImprovementMesh.h"

#include <algorithm>
#include <cmath>

#include "Error.h"
#include "mesh/Quality.h"
#include "mesh/Topology.h"

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
  collapsed_into_.assign(points_.size(), -1);
  original_vertices_ = points_.size();
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
    const auto sofar = volume_change_.find(material);
    const double before = sofar == volume_change_.end() ? 0 : sofar->second;
    if (std::abs(before + dv) > curved_volume_bound_ * std::abs(total->second)) return false;
  }
  return true;
}

void ImprovementMesh::addVolumeChange(const std::map<int, double>& change) {
  for (const auto& [material, dv] : change) volume_change_[material] += dv;
}

double ImprovementMesh::largestVolumeShareChanged() const {
  double share = 0;
  for (const auto& [material, net] : volume_change_) {
    const double total = std::abs(material_volume_.at(material));
    if (total > 0) share = std::max(share, std::abs(net) / total);
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

std::vector<std::array<int64_t, 3>> ImprovementMesh::facesAt(int64_t v) const {
  std::vector<std::array<int64_t, 3>> faces;
  for (int64_t t : vertex_tets_[v]) {
    const TetCorners& c = tets_[t];
    for (int skip = 0; skip < 4; ++skip) {
      if (c[skip] == v) continue;
      std::array<int64_t, 3> f;
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) f[j++] = c[k];
      const auto key = faceKey(f[0], f[1], f[2]);
      if (std::find(faces.begin(), faces.end(), key) == faces.end()) faces.push_back(key);
    }
  }
  return faces;
}

std::vector<std::array<int64_t, 3>> ImprovementMesh::outerFacesAt(int64_t v) const {
  std::vector<std::array<int64_t, 3>> outer;
  for (const auto& f : facesAt(v))
    if (tetsWithFace(f[0], f[1], f[2]).size() == 1) outer.push_back(f);
  return outer;
}

void ImprovementMesh::collapse(int64_t v, int64_t u) {
  ++clock_;
  const std::vector<int64_t> star = vertex_tets_[v];
  std::vector<int64_t> around;  // every vertex of v's tets
  for (int64_t t : star)
    for (int64_t w : tets_[t]) {
      changed_at_[w] = clock_;
      if (std::find(around.begin(), around.end(), w) == around.end()) around.push_back(w);
    }
  // Protected faces and edges at v: renamed, or gone when they have u too.
  std::vector<std::array<int64_t, 3>> renamedFaces;
  for (auto f : facesAt(v)) {
    if (!protected_faces_.erase(f)) continue;
    if (std::find(f.begin(), f.end(), u) != f.end()) continue;
    for (int64_t& w : f)
      if (w == v) w = u;
    renamedFaces.push_back(faceKey(f[0], f[1], f[2]));
  }
  for (const auto& f : renamedFaces) protected_faces_.insert(f);
  int64_t otherFeatureNeighbour = -1;
  for (int64_t w : around) {
    if (w == v || !protected_edges_.erase({std::min(v, w), std::max(v, w), -1})) continue;
    if (w == u) continue;
    protected_edges_.insert({std::min(u, w), std::max(u, w), -1});
    otherFeatureNeighbour = w;
  }
  // The tets: those with u go, the others have u for v.
  for (int64_t t : star) {
    TetCorners& c = tets_[t];
    if (std::find(c.begin(), c.end(), u) != c.end()) {
      alive_[t] = 0;
      for (int64_t w : c) {
        if (w == v) continue;
        auto& list = vertex_tets_[w];
        list.erase(std::find(list.begin(), list.end(), t));
      }
      continue;
    }
    for (int64_t& w : c)
      if (w == v) w = u;
    vertex_tets_[u].push_back(t);
  }
  vertex_tets_[v].clear();
  // What bounds the neighbours' moves: their boundary triangles and feature neighbours.
  for (int64_t w : around) {
    if (w == v) continue;
    VertexMobility& m = mobility_[w];
    for (auto& tri : m.boundary_triangles)
      for (int64_t& x : tri)
        if (x == v) x = u;
    m.boundary_triangles.erase(std::remove_if(m.boundary_triangles.begin(), m.boundary_triangles.end(),
                                              [](const std::array<int64_t, 3>& tri) {
                                                return tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2];
                                              }),
                               m.boundary_triangles.end());
    for (int64_t& x : m.feature_neighbours)
      if (x == v) x = w == u ? otherFeatureNeighbour : u;
  }
  VertexMobility& onto = mobility_[u];
  if (onto.freedom == VertexFreedom::Planar || onto.freedom == VertexFreedom::Curved ||
      onto.freedom == VertexFreedom::OnCurve)
    for (const auto& f : renamedFaces)
      if (std::find(onto.boundary_triangles.begin(), onto.boundary_triangles.end(), f) == onto.boundary_triangles.end())
        onto.boundary_triangles.push_back(f);
  mobility_[v] = VertexMobility{};
  collapsed_into_[v] = u;
  ++removed_vertices_;
}

void ImprovementMesh::flipProtectedFaces(int64_t a, int64_t b, int64_t c, int64_t d) {
  const std::array<std::array<int64_t, 3>, 2> gone{faceKey(a, b, c), faceKey(a, b, d)};
  const std::array<std::array<int64_t, 3>, 2> made{faceKey(a, c, d), faceKey(b, c, d)};
  for (const auto& f : gone) protected_faces_.erase(f);
  for (const auto& f : made) protected_faces_.insert(f);
  for (int64_t v : {a, b, c, d}) {
    auto& list = mobility_[v].boundary_triangles;
    if (list.empty()) continue;  // no move of v is bounded by its triangles
    list.erase(std::remove_if(list.begin(), list.end(),
                              [&](const std::array<int64_t, 3>& t) {
                                const auto key = faceKey(t[0], t[1], t[2]);
                                return key == gone[0] || key == gone[1];
                              }),
               list.end());
    for (const auto& f : made)
      if (std::find(f.begin(), f.end(), v) != f.end()) list.push_back(f);
  }
  surface_flipped_ = true;
}

int64_t ImprovementMesh::addVertex(const Point3& p) {
  const int64_t v = static_cast<int64_t>(points_.size());
  points_.push_back(p);
  vertex_tets_.emplace_back();
  VertexMobility free;
  free.freedom = VertexFreedom::Free;
  mobility_.push_back(free);
  changed_at_.push_back(++clock_);
  collapsed_into_.push_back(-1);
  ++added_vertices_;
  return v;
}

std::vector<int64_t> ImprovementMesh::writeBack(TetMesh& mesh) const {
  mesh.tets.clear();
  mesh.tet_materials.clear();
  for (size_t t = 0; t < tets_.size(); ++t)
    if (alive_[t]) {
      mesh.tets.push_back(tets_[t]);
      mesh.tet_materials.push_back(materials_[t]);
    }
  if (removed_vertices_ == 0 && added_vertices_ == 0) {
    if (surface_flipped_) mesh.boundary = extractBoundary(mesh);
    return {};
  }
  const size_t n = collapsed_into_.size();
  auto extend = [&](auto& perVertex, auto value) {
    if (perVertex.size() == original_vertices_) perVertex.resize(n, value);
  };
  extend(mesh.vertex_dimension, 3);
  extend(mesh.vertex_curve, -1);
  extend(mesh.vertex_boundary_entry, -1);
  auto finalVertex = [&](int64_t v) {
    while (collapsed_into_[v] >= 0) v = collapsed_into_[v];
    return v;
  };
  std::vector<int64_t> newIndex(n, -1), oldIndex;
  for (size_t v = 0; v < n; ++v)
    if (collapsed_into_[v] < 0) {
      newIndex[v] = static_cast<int64_t>(oldIndex.size());
      oldIndex.push_back(static_cast<int64_t>(v));
    }
  for (auto& c : mesh.tets)
    for (int64_t& v : c) v = newIndex[v];
  std::vector<std::array<int64_t, 2>> edges;
  std::vector<int> curves;
  for (size_t i = 0; i < mesh.feature_edges.size(); ++i) {
    const int64_t a = finalVertex(mesh.feature_edges[i][0]), b = finalVertex(mesh.feature_edges[i][1]);
    if (a == b) continue;  // the collapsed edge itself
    edges.push_back({newIndex[a], newIndex[b]});
    if (i < mesh.feature_edge_curves.size()) curves.push_back(mesh.feature_edge_curves[i]);
  }
  mesh.feature_edges = std::move(edges);
  if (!mesh.feature_edge_curves.empty()) mesh.feature_edge_curves = std::move(curves);
  auto compact = [&](auto& perVertex) {
    if (perVertex.size() != n) return;
    std::remove_reference_t<decltype(perVertex)> kept;
    kept.reserve(oldIndex.size());
    for (int64_t v : oldIndex) kept.push_back(perVertex[v]);
    perVertex = std::move(kept);
  };
  compact(mesh.points);
  compact(mesh.vertex_dimension);
  compact(mesh.vertex_curve);
  compact(mesh.vertex_boundary_entry);
  for (int64_t& v : oldIndex)
    if (v >= static_cast<int64_t>(original_vertices_)) v = -1;
  mesh.boundary.clear();  // in the old numbering
  mesh.boundary = extractBoundary(mesh);
  return oldIndex;
}

}  // namespace oraclemesh
