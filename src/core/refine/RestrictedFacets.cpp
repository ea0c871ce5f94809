// T2 of Rule Set T (thesis §3.3.1): a restricted facet is bad when a vertex is not on the
// boundary or its surface Delaunay ball is too big for facet_size / facet_distance /
// facet_angle (FacetCriteria.h): T2.1 its ball centre encroaches a subsegment -> split that
// subsegment, T2.2 else insert the ball centre. A facet is restricted when its dual Voronoi
// edge crosses the composite boundary (the multi-label setting of Pons et al. 2007).
#include <algorithm>
#include <cmath>
#include <limits>

#include "Error.h"
#include "refine/FacetCriteria.h"
#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {

// The dual Voronoi edge of facet (c, i): circumcentre to circumcentre, or a ray from the
// finite cell's circumcentre through the facet's outside, clipped far outside the domain.
void RuleSetTRefiner::dualOf(CH c, int i, Point3& from, Point3& to, int& labelFrom, int& labelTo) const {
  CH n = c->neighbor(i);
  CH finite = dt_.is_infinite(c) ? n : c;
  CH other = finite == c ? n : c;
  from = finite->info().circumcentre;
  labelFrom = finite->info().centreLabel;
  if (!dt_.is_infinite(other)) {
    to = other->info().circumcentre;
    labelTo = other->info().centreLabel;
    return;
  }
  const int fi = finite == c ? i : n->index(c);
  const CgalPoint& p0 = finite->vertex((fi + 1) & 3)->point();
  const CgalPoint& p1 = finite->vertex((fi + 2) & 3)->point();
  const CgalPoint& p2 = finite->vertex((fi + 3) & 3)->point();
  K::Vector_3 normal = CGAL::cross_product(p1 - p0, p2 - p0);
  if (CGAL::scalar_product(normal, finite->vertex(fi)->point() - p0) > 0) normal = -normal;
  const double len = std::sqrt(normal.squared_length());
  const Point3 direction = len > 0 ? Point3{normal.x() / len, normal.y() / len, normal.z() / len} : Point3{0, 0, 0};
  const Point3 middle = 0.5 * (oracle_.bbox().min + oracle_.bbox().max);
  to = from + (reach_ + distance(from, middle)) * direction;
  labelTo = 0;  // beyond every input
}

// The widest empty space between two parts that the dual edge a->b crosses: for each stretch
// outside every material between two crossings, the distance from each end to the surface
// the other end is on, the smaller of the two (a dual edge may cross a gap obliquely; its
// stretch there is longer than the gap is wide). Only stretches longer than `narrow` are
// measured (projections cost), narrower ones are no gap wider than it; nor are stretches no
// wider than a wedge bonded there (sizing/BondedWedges.h).
double RuleSetTRefiner::bridgedGap(const std::vector<CompositeCrossing>& crossings, double narrow) const {
  double widest = 0;
  for (size_t k = 0; k + 1 < crossings.size(); ++k) {
    const CompositeCrossing& from = crossings[k];
    const CompositeCrossing& to = crossings[k + 1];
    if (from.labelAfter != 0 || distance(from.point, to.point) <= narrow) continue;
    const auto& entries = oracle_.entries();
    const double width = std::min(entries[to.entry].source->project(from.point).distance,
                                  entries[from.entry].source->project(to.point).distance);
    if (width <= options_.criteria.bondedWidthAt(0.5 * (from.point + to.point))) continue;
    widest = std::max(widest, width);
  }
  return widest;
}

bool RuleSetTRefiner::contactEnds(int materialA, int materialB) const {
  return contactEndMaterials_.count(materialA) && contactEndMaterials_.count(materialB);
}

// Whether vertex v is inside a part of `material` or within the contact tolerance (or a bonded
// wedge's width) of its surface. A vertex put on an entry's boundary lies on that entry exactly.
bool RuleSetTRefiner::nearMaterial(VH v, int material) const {
  const auto& entries = oracle_.entries();
  const int own = v->info().boundaryEntry;
  if (own >= 0 && entries[own].material == material) return true;
  auto [it, inserted] = nearMaterial_.try_emplace({v->info().id, material}, false);
  if (!inserted) return it->second;
  const double tolerance = options_.criteria.bondedWidthAt(toPoint3(v->point()));
  return it->second = oracle_.distanceToMaterial(toPoint3(v->point()), material, tolerance) <= tolerance;
}

// Whether a corner of facet (c, i) lies farther than the contact tolerance from a part of
// one of the two materials the facet lies between.
bool RuleSetTRefiner::offInterface(CH c, int i, int materialA, int materialB) const {
  for (int k = 1; k < 4; ++k) {
    const VH w = c->vertex((i + k) & 3);
    if (dt_.is_infinite(w) || w->info().dimension == 3) continue;  // T2's own premise fails
    if (!nearMaterial(w, materialA) || !nearMaterial(w, materialB)) return true;
  }
  return false;
}

// The B-rep face a dimension-2 vertex lies on, projected once per position (rule P moves
// vertices); -1 for other vertices and for entries that are no B-rep.
int RuleSetTRefiner::patchOf(VH v) const {
  VertexInfo& info = v->info();
  const int entry = info.boundaryEntry;
  if (info.dimension != 2 || entry < 0 || !oracle_.entries()[entry].source->brepTopology()) return -1;
  const Point3 at = toPoint3(v->point());
  if (!(info.patchReadAt == at)) {
    info.patch = oracle_.entries()[entry].source->project(at).patch;
    info.patchReadAt = at;
  }
  return info.patch;
}

// Whether two corners of facet (c, i) lie on two faces of one B-rep that meet at a small
// dihedral angle: the facet then spans the wedge beside that edge instead of having the edge's
// chain of subsegments as an edge, and the mesh's boundary leaves the CAD there.
bool RuleSetTRefiner::acrossSharpEdge(CH c, int i) const {
  const auto& pairs = options_.faces_meeting_at_small_dihedrals;
  if (pairs.empty()) return false;
  // Only the parts with such an edge have their vertices' faces projected.
  const auto hasPair = [&](int entry) {
    const auto it = pairs.lower_bound({entry, std::numeric_limits<int>::min(), std::numeric_limits<int>::min()});
    return it != pairs.end() && std::get<0>(*it) == entry;
  };
  std::array<std::pair<int, int>, 3> onFace;  // (entry, face) of each corner, (-1, -1) if none
  for (int k = 0; k < 3; ++k) {
    const VH w = c->vertex((i + 1 + k) & 3);
    onFace[k] = {-1, -1};
    if (dt_.is_infinite(w) || !hasPair(w->info().boundaryEntry)) continue;
    const int patch = patchOf(w);
    if (patch >= 0) onFace[k] = {w->info().boundaryEntry, patch};
  }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const auto [entryA, faceA] = onFace[a];
      const auto [entryB, faceB] = onFace[b];
      if (faceA < 0 || faceB < 0 || entryA != entryB || faceA == faceB) continue;
      if (pairs.count({entryA, std::min(faceA, faceB), std::max(faceA, faceB)})) return true;
    }
  return false;
}

void RuleSetTRefiner::evaluateFacet(CH c, int i) {
  CH n = c->neighbor(i);
  const int j = n->index(c);
  FacetData data;
  data.known = true;
  if (!(dt_.is_infinite(c) && dt_.is_infinite(n))) {
    Point3 from, to;
    int labelFrom, labelTo;
    dualOf(c, i, from, to, labelFrom, labelTo);
    // Like Mesh_3's labeled domain, a dual edge whose ends have the same label is taken
    // as not crossing (it would have to cross twice within one Voronoi edge).
    if (labelFrom != labelTo && distance(from, to) > 0) {
      std::vector<CompositeCrossing> crossings;
      try {
        crossings = oracle_.crossings(from, to);
      } catch (const Error&) {
        crossings.clear();
      }
      // Several crossings: the ball of the farthest one is the one to meet the criteria.
      const CgalPoint& corner = c->vertex((i + 1) & 3)->point();
      double best = -1;
      for (const CompositeCrossing& x : crossings) {
        const double r2 = CGAL::squared_distance(toCgal(x.point), corner);
        if (r2 > best) {
          best = r2;
          data.restricted = true;
          data.centre = x.point;
          data.labelA = x.labelBefore;
          data.labelB = x.labelAfter;
          data.entry = x.entry;
        }
      }
      if (labelFrom > 0 && labelTo > 0 && contactEnds(labelFrom, labelTo))
        data.bridge = bridgedGap(crossings, options_.criteria.contact_tolerance);
      if (data.restricted && data.labelA > 0 && data.labelB > 0 && contactEnds(data.labelA, data.labelB))
        data.offInterface = offInterface(c, i, data.labelA, data.labelB);
      if (data.restricted) data.acrossSharpEdge = acrossSharpEdge(c, i);
    }
  }
  c->info().facets[i] = data;
  n->info().facets[j] = data;
  if (data.restricted) {
    const double priority = facetBadness(c, i);
    if (priority > 0) facetQueue_.push({priority, c->info().stamp, c, i});
  }
}

// How far a restricted facet is beyond its criteria (> 1: bad); 0 when good.
double RuleSetTRefiner::facetBadness(CH c, int i, std::string* reason, bool withAngle) const {
  const FacetData& f = c->info().facets[i];
  if (!f.restricted) return 0;
  FacetShape shape;
  shape.ballCentre = f.centre;
  shape.labelA = f.labelA;
  shape.labelB = f.labelB;
  shape.bridge = f.bridge;
  shape.offInterface = f.offInterface;
  shape.acrossSharpEdge = f.acrossSharpEdge;
  VH corners[3];
  for (int k = 0; k < 3; ++k) {
    corners[k] = c->vertex((i + 1 + k) & 3);
    if (dt_.is_infinite(corners[k]) || corners[k]->info().dimension == 3) {
      shape.cornersOnBoundary = false;
      break;
    }
    shape.corners[k] = toPoint3(corners[k]->point());
  }
  CriteriaTable::FieldValues below;
  const bool bounded = shape.cornersOnBoundary && options_.criteria.varies();
  if (bounded) below = fieldsBelow(shape.ballCentre, corners, 3);
  const FacetVerdict verdict = FacetCriteria(options_.criteria).judge(shape, withAngle, bounded ? &below : nullptr);
  if (reason && verdict.badness > 0) *reason = verdict.reason;
  return verdict.badness;
}

bool RuleSetTRefiner::refineOneFacet() {
  while (!facetQueue_.empty()) {
    const QueueEntry e = facetQueue_.top();
    facetQueue_.pop();
    if (e.cell->info().stamp != e.stamp) continue;  // the cell is gone or re-evaluated
    if (facetBadness(e.cell, e.facet) <= 0) continue;
    const Point3 centre = e.cell->info().facets[e.facet].centre;
    const Zone zone = examine(centre, e.cell);
    if (zone.duplicate) {
      leave("facet", "its surface Delaunay ball centre is a vertex already", e.stamp, e.facet);
      continue;
    }
    if (zone.encroached >= 0) {
      if (facetAngleTerminatorRefuses(e, zone.encroached)) continue;
      // T2.1: the ball centre encroaches a subsegment: split the subsegment instead.
      if (belowTerminator(segments_[zone.encroached])) {
        leave("facet", "its ball centre encroaches a subsegment shorter than the terminator length", e.stamp, e.facet);
        continue;
      }
      if (splitEncroached(zone.encroached, "T2.1")) return requeue(facetQueue_, e);
      leave("facet", "the subsegment its ball centre encroaches cannot be split", e.stamp, e.facet);
      continue;
    }
    if (belowTerminator(zone)) {
      leave("facet", "its ball centre is closer than the terminator length to a vertex", e.stamp, e.facet);
      continue;
    }
    commit(zone, 2, -1, e.cell->info().facets[e.facet].entry);  // T2.2
    ++stats_.insertions["T2.2"];
    return true;
  }
  return false;
}

// Terminator for the facet angle (beyond the thesis, like T3's for the radius-edge ratio).
// Where two feature curves meet at a small angle (part.step: a line tangent to an arc, 0
// degrees) the facets between them keep that angle however fine they get, and the T2.1
// splits of the subsegments their ball centres encroach put ever closer pairs of segment
// vertices onto the two curves, each pair a sliver that CGAL's perturbation (which keeps
// segment vertices fixed) then works on in vain (part.step with the T1.2 terminator alone:
// 67 T2.1 splits, 150 s of perturbation, 0.26 degrees; with this one: 14, 20 s, 1.2). A
// facet that meets its size and distance bounds and fails only facet_angle there is left.
bool RuleSetTRefiner::facetAngleTerminatorRefuses(const QueueEntry& e, int s) {
  if (!nearSmallAngle(segments_[s]) || facetBadness(e.cell, e.facet, nullptr, false) > 0) return false;
  leave("facet", "T2.1 would split a subsegment next to an input angle under 60 degrees for the facet angle alone",
        e.stamp, e.facet);
  return true;
}

// The surface Delaunay ball of a restricted facet of the conflict zone that contains p.
// entry (if given): the oracle entry whose boundary the centre is on.
bool RuleSetTRefiner::surfaceBallContaining(const Zone& zone, Point3& centre, int* entry) const {
  for (CH c : zone.cells)
    for (int i = 0; i < 4; ++i) {
      const FacetData& f = c->info().facets[i];
      if (!f.restricted) continue;
      const CgalPoint ballCentre = toCgal(f.centre);
      const double r2 = CGAL::squared_distance(ballCentre, c->vertex((i + 1) & 3)->point());
      if (CGAL::squared_distance(zone.point, ballCentre) < r2) {
        centre = f.centre;
        if (entry) *entry = f.entry;
        return true;
      }
    }
  return false;
}

}  // namespace oraclemesh::refine
