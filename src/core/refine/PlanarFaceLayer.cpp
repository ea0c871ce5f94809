// TP, the planar-face layer: see PlanarFaceLayer.h; the planar side (frames, the 2D
// triangulation, the restriction to the face) is PlanarFacets.cpp.
#include "refine/PlanarFaceLayer.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "refine/PlanarFacets.h"

namespace oraclemesh::refine {

void PlanarFaceLayer::vertexAdded(VH v) {
  vertices_.resize(faces_.size());
  facesOfVertex_.resize(static_cast<size_t>(v->info().id) + 1);
  if (v->info().far) return;
  const Point3 p = toPoint3(v->point());
  for (size_t f = 0; f < faces_.size(); ++f) {
    const PlanarFace& face = faces_[f];
    if (!face.box.contains(p) || std::abs(face.height(p)) > core_.oracle().tolerance()) continue;
    vertices_[f].push_back(v);
    facesOfVertex_[v->info().id].push_back(static_cast<int>(f));
  }
}

bool PlanarFaceLayer::labelsByBarycentre(CH c) const {
  if (facesOfVertex_.empty()) return false;
  const Delaunay& dt = core_.triangulation();
  for (int a = 0; a < 4; ++a) {
    if (dt.is_infinite(c->vertex(a))) return false;
    const auto& fa = facesOfVertex_[c->vertex(a)->info().id];
    if (fa.empty()) continue;
    for (int b = a + 1; b < 4; ++b) {
      if (dt.is_infinite(c->vertex(b))) return false;
      for (int f : facesOfVertex_[c->vertex(b)->info().id])
        if (std::find(fa.begin(), fa.end(), f) != fa.end()) return true;
    }
  }
  return false;
}

// The planar face all four corners of a cell lie on, or -1.
int PlanarFaceLayer::faceOfCell(CH c) const {
  if (facesOfVertex_.empty()) return -1;
  const Delaunay& dt = core_.triangulation();
  for (int k = 0; k < 4; ++k)
    if (dt.is_infinite(c->vertex(k))) return -1;
  for (int f : facesOfVertex_[c->vertex(0)->info().id]) {
    bool all = true;
    for (int k = 1; k < 4 && all; ++k) {
      const auto& faces = facesOfVertex_[c->vertex(k)->info().id];
      all = std::find(faces.begin(), faces.end(), f) != faces.end();
    }
    if (all) return f;
  }
  return -1;
}

bool PlanarFaceLayer::pinsVertex(VH v) const {
  return !facesOfVertex_.empty() && !facesOfVertex_[v->info().id].empty();
}

std::array<int64_t, 3> PlanarFaceLayer::cornerKey(const std::array<VH, 3>& corners) {
  std::array<int64_t, 3> key{corners[0]->info().id, corners[1]->info().id, corners[2]->info().id};
  std::sort(key.begin(), key.end());
  return key;
}

bool PlanarFaceLayer::isFacet(const std::array<VH, 3>& corners) const {
  CH c;
  int i, j, k;
  return core_.triangulation().is_facet(corners[0], corners[1], corners[2], c, i, j, k);
}

// The restricted 2D Delaunay triangles of face f; only those that are no 3D facet when
// `missingOnly`.
std::vector<PlanarFaceLayer::QueuedTriangle> PlanarFaceLayer::triangles(size_t f, bool missingOnly) const {
  const std::vector<VH>& vertices = vertices_[f];
  std::vector<Point3> points;
  points.reserve(vertices.size());
  for (VH v : vertices) points.push_back(toPoint3(v->point()));
  auto cornersOf = [&](const std::array<int, 3>& t) {
    return std::array<VH, 3>{vertices[t[0]], vertices[t[1]], vertices[t[2]]};
  };
  std::function<bool(const std::array<int, 3>&)> wanted;
  if (missingOnly) wanted = [&](const std::array<int, 3>& t) { return !isFacet(cornersOf(t)); };
  std::vector<QueuedTriangle> result;
  for (const PlanarTriangle& t : restrictedPlanarTriangles(faces_[f], points, core_.oracle(), wanted))
    result.push_back({static_cast<int>(f), cornersOf(t.corners), t.circumcentre, t.radius, vertices.size()});
  return result;
}

// At a fixpoint of the other rules: queues the planar triangles the 3D triangulation lacks.
// True when there are some and the triangulation changed since the last look (otherwise
// the answer, and what the layer can do about it, are the same as last time).
bool PlanarFaceLayer::queuesEmptied() {
  const Delaunay& dt = core_.triangulation();
  const int64_t vertices = static_cast<int64_t>(dt.number_of_vertices());
  if (vertices == verticesAtCheck_) return false;
  verticesAtCheck_ = vertices;
  queue_.clear();
  for (size_t f = 0; f < faces_.size(); ++f) {
    std::vector<QueuedTriangle> missing = triangles(f, true);
    queue_.insert(queue_.end(), missing.begin(), missing.end());
  }
  if (!checked_) core_.statistics().planar.missing_at_first_check = static_cast<int64_t>(queue_.size());
  checked_ = true;
  // Flat cells on a face whatever their label (one labelled outside between two materials
  // would be a gap of no thickness in the interface).
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    const int f = faceOfCell(c);
    if (f < 0) continue;
    QueuedTriangle flat;
    flat.face = f;
    flat.corners = {c->vertex(0), c->vertex(1), c->vertex(2)};
    flat.circumcentre = c->info().circumcentre;
    flat.radius = c->info().radius;
    flat.pointsAtCheck = vertices_[f].size();
    flat.flatCell = c;
    flat.flatStamp = c->info().stamp;
    queue_.push_back(flat);
  }
  // Popped from the back: the largest circumradius first; ties in a stable order.
  std::stable_sort(queue_.begin(), queue_.end(),
                   [](const QueuedTriangle& a, const QueuedTriangle& b) { return a.radius < b.radius; });
  return !queue_.empty();
}

// A vertex put on the face since the triangle was found lies inside its circumcircle: the
// triangle is no longer one of the face's 2D Delaunay triangles.
bool PlanarFaceLayer::triangleGone(const QueuedTriangle& t) const {
  const std::vector<VH>& vertices = vertices_[t.face];
  for (size_t k = t.pointsAtCheck; k < vertices.size(); ++k)
    if (distance(toPoint3(vertices[k]->point()), t.circumcentre) < t.radius * (1 - 1e-9)) return true;
  return false;
}

bool PlanarFaceLayer::refineOne() {
  RuleSetTStatistics& stats = core_.statistics();
  while (!queue_.empty()) {
    const QueuedTriangle t = queue_.back();
    queue_.pop_back();
    if (t.flatCell != CH() ? t.flatCell->info().stamp != t.flatStamp : isFacet(t.corners)) continue;
    if (triangleGone(t)) continue;
    auto leaveTriangle = [&](const std::string& why) { left_[cornerKey(t.corners)] = why; };
    if (t.radius < core_.terminatorAt(t.circumcentre)) {
      leaveTriangle("its circumradius is below the terminator length");
      continue;
    }
    const Zone zone = core_.examine(t.circumcentre, t.corners[0]->cell());
    if (zone.duplicate) {
      leaveTriangle("its circumcentre is a vertex already");
      continue;
    }
    if (zone.encroached >= 0) {  // TP.1
      if (core_.belowTerminator(core_.segments()[zone.encroached])) {
        leaveTriangle("its circumcentre encroaches a subsegment shorter than the terminator length");
        continue;
      }
      if (core_.splitEncroached(zone.encroached, "TP.1")) {
        ++stats.planar.insertions;
        return true;
      }
      leaveTriangle("the subsegment its circumcentre encroaches cannot be split");
      continue;
    }
    // Only a point of the face itself goes in, exactly where the oracle puts the face.
    Point3 onFace;
    if (!onCompositeFace(faces_[t.face], t.circumcentre, core_.oracle(), &onFace)) {
      leaveTriangle("its circumcentre lies off the face's part of the composite boundary");
      continue;
    }
    if (core_.insertIfFree(onFace, t.corners[0]->cell(), 2, -1, faces_[t.face].entry) == VH()) {  // TP.2
      leaveTriangle("its circumcentre is closer than the terminator length to a vertex");
      continue;
    }
    ++stats.insertions["TP.2"];
    ++stats.planar.insertions;
    return true;
  }
  return false;
}

void PlanarFaceLayer::refinementDone() {
  constexpr size_t kListed = 200;
  PlanarFaceStatistics& s = core_.statistics().planar;
  s.faces = s.triangles = s.missing = 0;
  s.missing_triangles.clear();
  for (size_t f = 0; f < faces_.size(); ++f) {
    const std::vector<QueuedTriangle> found = triangles(f, false);
    if (found.empty()) continue;
    ++s.faces;
    s.triangles += static_cast<int64_t>(found.size());
    for (const QueuedTriangle& t : found) {
      if (isFacet(t.corners)) continue;
      ++s.missing;
      if (s.missing_triangles.size() >= kListed) continue;
      const PlanarFace& face = faces_[f];
      auto why = left_.find(cornerKey(t.corners));
      s.missing_triangles.push_back({face.entry, face.face, t.circumcentre, t.radius,
                                     why != left_.end() ? why->second : "not refined"});
    }
  }
}

}  // namespace oraclemesh::refine
