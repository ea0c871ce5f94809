#include "improve/MeshImprovement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>
#include <vector>

#include "improve/EdgeCollapse.h"
#include "improve/EdgeRemoval.h"
#include "improve/FaceRemoval.h"
#include "improve/ImprovementMesh.h"
#include "improve/Smoothing.h"
#include "improve/SurfaceFlip.h"
#include "improve/VertexInsertion.h"
#include "mesh/Quality.h"

namespace oraclemesh {
namespace {

constexpr int kEdgeCorners[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

double meshMinDihedral(const TetMesh& mesh) {
  double m = 180;
  for (const auto& t : mesh.tets) m = std::min(m, smallestDihedral(mesh.points, t));
  return mesh.tets.empty() ? 0 : m;
}

double boundingDiagonal(const std::vector<Point3>& points) {
  Point3 low = points.front(), high = points.front();
  for (const Point3& q : points)
    for (int i = 0; i < 3; ++i) {
      low[i] = std::min(low[i], q[i]);
      high[i] = std::max(high[i], q[i]);
    }
  return distance(low, high);
}

void countPoorTet(PoorTetCounts& c, double quality) {
  c.under5 += quality < 5;
  c.under10 += quality < 10;
  c.under15 += quality < 15;
}

PoorTetCounts countPoorTets(const TetMesh& mesh) {
  PoorTetCounts c;
  for (const auto& t : mesh.tets) countPoorTet(c, smallestDihedral(mesh.points, t));
  return c;
}

PoorTetCounts countPoorTets(const ImprovementMesh& mesh, double& smallest) {
  PoorTetCounts c;
  smallest = 180;
  for (int64_t t = 0; t < mesh.tetSlots(); ++t)
    if (mesh.alive(t)) {
      const double q = mesh.quality(t);
      smallest = std::min(smallest, q);
      countPoorTet(c, q);
    }
  return c;
}

// Alive tets under the goal, worst first, ties by index.
std::vector<std::pair<double, int64_t>> worstFirst(const ImprovementMesh& mesh, double goal) {
  std::vector<std::pair<double, int64_t>> order;
  for (int64_t t = 0; t < mesh.tetSlots(); ++t)
    if (mesh.alive(t)) {
      const double q = mesh.quality(t);
      if (q < goal) order.push_back({q, t});
    }
  std::sort(order.begin(), order.end());
  return order;
}

class Driver {
 public:
  Driver(ImprovementMesh& mesh, const ImprovementOptions& options, const RunControl& control, ImprovementStats& stats)
      : mesh_(mesh), options_(options), control_(control), stats_(stats), start_(std::chrono::steady_clock::now()),
        vertex_tried_(mesh.points().size(), -1) {}

  // A tet tried before (`tried`: the clock when each tet was last tried by one operation kind)
  // is tried again only when something around one of its corners changed.
  bool changedSinceTried(const std::vector<int64_t>& tried, int64_t t) const {
    if (t >= static_cast<int64_t>(tried.size()) || tried[t] < 0) return true;
    for (int64_t v : mesh_.tet(t))
      if (mesh_.changedAt(v) > tried[t]) return true;
    return false;
  }

  // Records that tet t is being tried now.
  void markTried(std::vector<int64_t>& tried, int64_t t) const {
    if (static_cast<int64_t>(tried.size()) < mesh_.tetSlots()) tried.resize(mesh_.tetSlots(), -1);
    tried[t] = mesh_.now();
  }

  bool outOfTime() {
    if (++operations_ % 256 == 0) control_.checkpoint();
    if (options_.time_limit <= 0) return false;
    if (elapsed() <= options_.time_limit) return false;
    stats_.stopped_by_time_limit = true;
    return true;
  }

  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  // Edge removal on the tet's edges, those at its most extreme dihedral angles first (a
  // sliver's small angles and a cap's large one), else face removal from one of its faces,
  // else a surface flip of one of its edges (SurfaceFlip.h), else a collapse.
  int64_t topologicalSweep() {
    int64_t changes = 0;
    for (const auto& [quality, t] : worstFirst(mesh_, options_.goal_deg)) {
      if (!mesh_.alive(t) || !changedSinceTried(tet_tried_, t)) continue;
      if (outOfTime()) break;
      const TetCorners c = mesh_.tet(t);
      markTried(tet_tried_, t);
      const auto& p = mesh_.points();
      const auto angles = dihedralAngles(p[c[0]], p[c[1]], p[c[2]], p[c[3]]);
      int edges[6] = {0, 1, 2, 3, 4, 5};
      std::stable_sort(edges, edges + 6, [&](int x, int y) {
        return std::abs(angles[x] - 90) > std::abs(angles[y] - 90);
      });
      bool done = false;
      for (int e : edges) {
        const int ring = removeEdge(mesh_, c[kEdgeCorners[e][0]], c[kEdgeCorners[e][1]], options_.sizes);
        if (ring == 0) continue;
        (ring == 3 ? stats_.flips32 : ring == 4 ? stats_.flips44 : stats_.edge_removals)++;
        done = true;
        break;
      }
      for (int f = 0; f < 4 && !done; ++f) {
        const int faces = removeFaces(mesh_, c[(f + 1) % 4], c[(f + 2) % 4], c[(f + 3) % 4], options_.sizes);
        if (faces == 0) continue;
        (faces == 1 ? stats_.flips23 : stats_.multi_face_removals)++;
        done = true;
      }
      for (int e = 0; e < 6 && !done && options_.surface_flips; ++e) {
        if (!flipSurfaceEdge(mesh_, c[kEdgeCorners[edges[e]][0]], c[kEdgeCorners[edges[e]][1]], options_.sizes,
                             options_.curved_cap_flatness))
          continue;
        ++stats_.surface_flips;
        done = true;
      }
      if (!done && options_.edge_collapse) done = collapseShortestEdge(c);
      changes += done;
    }
    return changes;
  }

  // The tet's edges shortest first, each end onto the other: a short edge is what makes a
  // sliver that no flip removes when its ends cannot move apart.
  bool collapseShortestEdge(const TetCorners& c) {
    const auto& p = mesh_.points();
    int edges[6] = {0, 1, 2, 3, 4, 5};
    std::stable_sort(edges, edges + 6, [&](int x, int y) {
      return distance(p[c[kEdgeCorners[x][0]]], p[c[kEdgeCorners[x][1]]]) <
             distance(p[c[kEdgeCorners[y][0]]], p[c[kEdgeCorners[y][1]]]);
    });
    for (int e : edges) {
      const int64_t a = c[kEdgeCorners[e][0]], b = c[kEdgeCorners[e][1]];
      if (collapseEdge(mesh_, a, b, options_.sizes) || collapseEdge(mesh_, b, a, options_.sizes)) {
        ++stats_.edge_collapses;
        return true;
      }
    }
    // A curve vertex of the tet onto a curve neighbour that is not: the short edge between the
    // first vertices of two curves leaving a corner at a small angle joins two curves, which no
    // collapse may merge, but one of those vertices can go farther out along its own curve,
    // where the curves are farther apart.
    for (int64_t v : c) {
      const VertexMobility& m = mesh_.mobility(v);
      if (m.freedom != VertexFreedom::Linear && m.freedom != VertexFreedom::OnCurve) continue;
      for (int64_t u : m.feature_neighbours)
        if (u >= 0 && std::find(c.begin(), c.end(), u) == c.end() && collapseEdge(mesh_, v, u, options_.sizes)) {
          ++stats_.edge_collapses;
          return true;
        }
    }
    return false;
  }

  // A new vertex for each tet still under the goal, worst first: the last resort, once flips,
  // collapses and smoothing have done what they can (inserting earlier took the place of moves
  // that did better, and the stage ended lower).
  int64_t insertionSweep() {
    int64_t changes = 0;
    for (const auto& [quality, t] : worstFirst(mesh_, options_.goal_deg)) {
      if (!mesh_.alive(t) || !changedSinceTried(insertion_tried_, t)) continue;
      if (outOfTime()) break;
      markTried(insertion_tried_, t);
      if (insertVertex(mesh_, t, options_.sizes) < 0) continue;
      ++stats_.vertex_insertions;
      ++changes;
    }
    return changes;
  }

  // Each vertex of a tet under the goal, once per pass, worst tet first.
  int64_t smoothingSweep() {
    int64_t changes = 0;
    std::vector<char> visited(mesh_.points().size(), 0);
    vertex_tried_.resize(mesh_.points().size(), -1);  // inserted vertices were never tried
    for (const auto& [quality, t] : worstFirst(mesh_, options_.goal_deg)) {
      if (!mesh_.alive(t)) continue;
      for (int64_t v : mesh_.tet(t)) {
        if (visited[v]) continue;
        visited[v] = 1;
        if (vertex_tried_[v] >= mesh_.changedAt(v)) continue;  // nothing near it changed since
        vertex_tried_[v] = mesh_.now();
        if (outOfTime()) return changes;
        if (!smoothVertex(mesh_, v, options_.sizes)) continue;
        ++changes;
        switch (mesh_.mobility(v).freedom) {
          case VertexFreedom::Free: ++stats_.smoothed_interior; break;
          case VertexFreedom::Planar: ++stats_.smoothed_surface; break;
          case VertexFreedom::Linear: ++stats_.smoothed_feature; break;
          case VertexFreedom::Curved: ++stats_.smoothed_curved_surface; break;
          default: ++stats_.smoothed_curved_feature; break;
        }
      }
    }
    return changes;
  }

 private:
  ImprovementMesh& mesh_;
  const ImprovementOptions& options_;
  const RunControl& control_;
  ImprovementStats& stats_;
  std::chrono::steady_clock::time_point start_;
  int64_t operations_ = 0;
  std::vector<int64_t> tet_tried_;     // clock when each tet was last tried, -1 never
  std::vector<int64_t> vertex_tried_;  // same for smoothing each vertex
  std::vector<int64_t> insertion_tried_;  // same for inserting a vertex in each tet
};

}  // namespace

ImprovementStats improveMesh(TetMesh& mesh, const ImprovementOptions& options, const RunControl& control,
                             std::vector<int64_t>* previousIndex) {
  ImprovementStats stats;
  stats.min_dihedral_before = meshMinDihedral(mesh);
  stats.before = countPoorTets(mesh);
  const auto start = std::chrono::steady_clock::now();
  if (options.flat_caps && !mesh.tets.empty())
    stats.flat_caps = removeFlatCaps(mesh, options.flat_cap_flatness * boundingDiagonal(mesh.points),
                                     options.flat_cap_volume_bound,
                                     options.placement ? CurvedCapLimits{options.curved_cap_flatness, options.curved_volume_bound}
                                                       : CurvedCapLimits{});
  ImprovementMesh work(mesh, options.placement, options.curved_volume_bound);
  Driver driver(work, options, control, stats);
  for (int pass = 0; pass < options.max_passes && !stats.stopped_by_time_limit; ++pass) {
    ++stats.passes;
    const int64_t changes = driver.topologicalSweep() + driver.smoothingSweep();
    if (changes == 0) break;
  }
  // Then insertion, each followed by the other operations around the new vertices.
  stats.before_insertion = countPoorTets(work, stats.min_dihedral_before_insertion);
  for (int pass = 0; options.vertex_insertion && pass < options.insertion_passes && !stats.stopped_by_time_limit;
       ++pass) {
    ++stats.passes;
    if (driver.insertionSweep() == 0) break;
    driver.topologicalSweep();
    driver.smoothingSweep();
  }
  std::vector<int64_t> renumbered = work.writeBack(mesh);
  if (previousIndex) *previousIndex = std::move(renumbered);
  stats.curved_volume_share = work.largestVolumeShareChanged();
  stats.min_dihedral_after = meshMinDihedral(mesh);
  stats.after = countPoorTets(mesh);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace oraclemesh
