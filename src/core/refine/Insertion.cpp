// The insertion core every level of the refiner inserts through. A point's conflict zone is
// found first (find_conflicts) and looked at before anything changes: which subsegments are
// edges of its cells and whether the point encroaches one, and how near the nearest vertex is.
// The callers decide from that what goes in (the point, or a redirection as T2.1 / T3.1), and
// insert_in_hole then reuses the zone. Inserting a vertex evaluates its new cells and facets
// and queues those that are bad; every subsegment of the zone is queued for T1 again.
#include <algorithm>
#include <cmath>
#include <limits>

#include "Error.h"
#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {

Zone RuleSetTRefiner::examine(const Point3& p, CH hint, int splitting) const {
  Zone zone;
  zone.point = toCgal(p);
  Delaunay::Locate_type lt;
  int li, lj;
  const CH located = dt_.locate(zone.point, lt, li, lj, hint);
  if (lt == Delaunay::VERTEX) {
    zone.duplicate = true;
    return zone;
  }
  std::vector<Facet> boundary;
  dt_.find_conflicts(zone.point, located, std::back_inserter(boundary), std::back_inserter(zone.cells));
  zone.boundaryFacet = boundary.front();
  double nearest = std::numeric_limits<double>::infinity();
  for (CH c : zone.cells) {
    for (int a = 0; a < 4; ++a) {
      VH va = c->vertex(a);
      if (dt_.is_infinite(va)) continue;
      nearest = std::min(nearest, CGAL::squared_distance(zone.point, va->point()));
      // Only an edge between two segment vertices can be a subsegment: the check spares
      // most conflict cells the hash lookups (a few % of the whole implant job).
      if (segmentsAt_[va->info().id].empty()) continue;
      for (int b = a + 1; b < 4; ++b) {
        VH vb = c->vertex(b);
        if (dt_.is_infinite(vb) || segmentsAt_[vb->info().id].empty()) continue;
        auto it = segmentOf_.find(pairKey(va->info().id, vb->info().id));
        if (it == segmentOf_.end()) continue;
        const int s = it->second;
        if (std::find(zone.segments.begin(), zone.segments.end(), s) != zone.segments.end()) continue;
        zone.segments.push_back(s);
        if (zone.encroached < 0 && s != splitting && strictlyInDiametralBall(zone.point, segments_[s]))
          zone.encroached = s;
      }
    }
  }
  zone.insertionRadius = std::sqrt(nearest);
  return zone;
}

VH RuleSetTRefiner::commit(const Zone& zone, int dimension, int curve, int boundaryEntry) {
  // Queue entries of the cells about to be deleted must read as stale.
  for (CH c : zone.cells) c->info().stamp = 0;
  VH v = dt_.insert_in_hole(zone.point, zone.cells.begin(), zone.cells.end(), zone.boundaryFacet.first,
                            zone.boundaryFacet.second);
  setInfo(v, dimension, curve);
  v->info().boundaryEntry = dimension == 2 ? boundaryEntry : -1;
  if (options_.max_vertices > 0 && static_cast<int64_t>(dt_.number_of_vertices()) > options_.max_vertices)
    throw LimitError("the thesis engine reached limits.max_vertices = " + std::to_string(options_.max_vertices) +
                     " vertices during refinement: coarsen cell_size / facet_size / facet_distance or raise the limit");
  afterInsertion(v);
  // Subsegments of the zone may have lost their Delaunay edge or be encroached by v.
  for (int s : zone.segments) pushSegment(s);
  return v;
}

bool RuleSetTRefiner::isFree(const Zone& zone) const {
  return !(zone.duplicate || zone.encroached >= 0 || belowTerminator(zone));
}

VH RuleSetTRefiner::insertIfFree(const Point3& p, CH hint, int dimension, int curve, int boundaryEntry) {
  const Zone zone = examine(p, hint);
  return isFree(zone) ? commit(zone, dimension, curve, boundaryEntry) : VH();
}

void RuleSetTRefiner::setInfo(VH v, int dimension, int curve, bool far) {
  v->info().id = nextVertexId_++;
  v->info().dimension = dimension;
  v->info().curve = curve;
  v->info().far = far;
  segmentsAt_.emplace_back();
  if (hook_) hook_->vertexAdded(v);
}

void RuleSetTRefiner::afterInsertion(VH v) {
  std::vector<CH> cells;
  dt_.incident_cells(v, std::back_inserter(cells));
  for (CH c : cells) evaluateCell(c);
  for (CH c : cells) {
    for (int i = 0; i < 4; ++i)
      if (!c->info().facets[i].known) evaluateFacet(c, i);
    const double bad = cellBadness(c);
    if (bad > 0) cellQueue_.push({bad, c->info().stamp, c, -1});
  }
}

void RuleSetTRefiner::leave(const std::string& kind, const std::string& reason, uint64_t stamp, int facet) {
  leftReasons_[{stamp, facet}] = kind + ": " + reason;
}

}  // namespace oraclemesh::refine
