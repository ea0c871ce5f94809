// What the refiner hands back: the cells inside the materials as a TetMesh with its
// constrained subsegments as feature edges, the final check of the guarantees by other means
// than the refinement uses, and the list of elements left that violate their criteria.
#include <algorithm>

#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {

// The corners of the cells inside the materials, in the order the mesh lists them: the
// triangulation's own order unless vertices have moved (rule P). CGAL's vertex removal,
// which a move uses, creates cells in an order of handle addresses, which differ between
// runs; the mesh (and the optimizers and snap that follow, which depend on its order) must
// not. Then cells are sorted by their corners' vertex ids, each cell starting at its
// smallest id with its orientation kept.
std::vector<RuleSetTRefiner::LabelledCell> RuleSetTRefiner::labelledCellsInOutputOrder() const {
  std::vector<LabelledCell> cells;
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c)
    if (c->info().label > 0) cells.push_back({{c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)}, c->info().label});
  if (stats_.vertex_moves == 0) return cells;
  auto id = [](VH v) { return v->info().id; };
  for (LabelledCell& cell : cells) {
    std::array<VH, 4>& corners = cell.corners;
    int parity = 0;  // bubble sort by id; each swap flips the orientation
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j + 1 < 4 - i; ++j)
        if (id(corners[j]) > id(corners[j + 1])) std::swap(corners[j], corners[j + 1]), parity ^= 1;
    if (parity) std::swap(corners[2], corners[3]);
  }
  std::sort(cells.begin(), cells.end(), [&](const LabelledCell& x, const LabelledCell& y) {
    for (int k = 0; k < 4; ++k)
      if (id(x.corners[k]) != id(y.corners[k])) return id(x.corners[k]) < id(y.corners[k]);
    return false;
  });
  return cells;
}

TetMesh RuleSetTRefiner::extract() const {
  TetMesh mesh;
  // Vertex ids count from 0 without gaps, so the mesh index of each is a plain lookup.
  std::vector<int64_t> index(static_cast<size_t>(nextVertexId_), -1);
  auto indexOf = [&](VH v) {
    int64_t& at = index[static_cast<size_t>(v->info().id)];
    if (at < 0) {
      at = static_cast<int64_t>(mesh.points.size());
      mesh.points.push_back(toPoint3(v->point()));
      mesh.vertex_dimension.push_back(v->info().dimension);
      mesh.vertex_curve.push_back(v->info().dimension == 1 ? v->info().curve : -1);
      mesh.vertex_boundary_entry.push_back(v->info().dimension == 2 ? v->info().boundaryEntry : -1);
    }
    return at;
  };
  for (const LabelledCell& cell : labelledCellsInOutputOrder()) {
    const std::array<VH, 4>& corners = cell.corners;
    mesh.tets.push_back({indexOf(corners[0]), indexOf(corners[1]), indexOf(corners[2]), indexOf(corners[3])});
    mesh.tet_materials.push_back(cell.label);
  }
  for (const Subsegment& s : segments_) {
    if (!s.alive) continue;
    const int64_t ia = index[static_cast<size_t>(s.a->info().id)], ib = index[static_cast<size_t>(s.b->info().id)];
    if (ia < 0 || ib < 0) continue;  // a constraint outside every material
    mesh.feature_edges.push_back({ia, ib});
    mesh.feature_edge_curves.push_back(s.curve);
  }
  return mesh;
}

void RuleSetTRefiner::finalCheck() {
  stats_.constrained_subsegments = stats_.subsegments_not_edges = stats_.encroached_subsegments = 0;
  stats_.subsegments_outside_material = 0;
  for (const Subsegment& s : segments_) {
    if (!s.alive) continue;
    ++stats_.constrained_subsegments;
    stats_.subsegments_outside_material += outsideEveryMaterial(s);
    CH c;
    int i, j;
    if (!dt_.is_edge(s.a, s.b, c, i, j)) ++stats_.subsegments_not_edges;
    // The nearest vertex to the midpoint is inside the diametral ball iff any vertex is.
    const CgalPoint m = CGAL::midpoint(s.a->point(), s.b->point());
    const VH nearest = dt_.nearest_vertex(m, s.a->cell());
    if (nearest != s.a && nearest != s.b && strictlyInDiametralBall(nearest->point(), s))
      ++stats_.encroached_subsegments;
  }
  stats_.restricted_facets_off_boundary = 0;
  for (auto c = dt_.all_cells_begin(); c != dt_.all_cells_end(); ++c)
    for (int i = 0; i < 4; ++i) {
      if (c->neighbor(i) < c || !c->info().facets[i].restricted) continue;
      for (int k = 1; k < 4; ++k) {
        VH v = c->vertex((i + k) & 3);
        if (dt_.is_infinite(v) || v->info().dimension == 3) {
          ++stats_.restricted_facets_off_boundary;
          break;
        }
      }
    }
}

void RuleSetTRefiner::listLeftElements() {
  constexpr size_t kListed = 200;  // the report lists the worst ones; the count is complete
  std::vector<std::pair<double, LeftElement>> left;
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
    std::string reason;
    const double bad = cellBadness(c, nullptr, &reason);
    if (bad > 0) {
      auto it = leftReasons_.find({c->info().stamp, -1});
      const std::string why = it != leftReasons_.end() ? it->second : "cell: not refined";
      left.push_back({bad, {"cell", reason + " (" + why + ")", c->info().circumcentre, c->info().label, bad}});
    }
  }
  for (auto c = dt_.all_cells_begin(); c != dt_.all_cells_end(); ++c)
    for (int i = 0; i < 4; ++i) {
      CH n = c->neighbor(i);
      if (n < c) continue;  // each facet once
      std::string reason;
      const double bad = facetBadness(c, i, &reason);
      if (bad <= 0) continue;
      auto it = leftReasons_.find({c->info().stamp, i});
      if (it == leftReasons_.end()) it = leftReasons_.find({n->info().stamp, n->index(c)});
      const std::string why = it != leftReasons_.end() ? it->second : "facet: not refined";
      const FacetData& f = c->info().facets[i];
      left.push_back({bad, {"facet", reason + " (" + why + ")", f.centre, std::max(f.labelA, f.labelB), bad}});
    }
  std::stable_sort(left.begin(), left.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  stats_.left.clear();
  for (auto& [bad, element] : left) stats_.left.push_back(std::move(element));
  stats_.elements_left_total = static_cast<int64_t>(left.size());
  if (stats_.left.size() > kListed) stats_.left.resize(kListed);
}

}  // namespace oraclemesh::refine
