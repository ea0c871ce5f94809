// T1 of Rule Set T (thesis §3.3.1): a constrained subsegment is bad when it is next to a star
// vertex and longer than l_min,i / 3 (T1.1: split at l_min,i / 3 from the star vertex), longer
// than another subsegment at the same star vertex (concentric shell split, see below), or
// encroached (T1.2: midpoint). Beyond the thesis:
//   - concentric shells (Shewchuk 1998): a subsegment at a star vertex that is longer than the
//     shortest one there is split at that shortest length from the star vertex, so all splits
//     around a star vertex happen on spheres of radius l_min,i / 3 / 2^k (counted "T1.2 shell");
//   - terminator: next to a small input angle a short subsegment that is still a Delaunay edge
//     is left encroached (encroachmentTerminatorRefuses);
//   - T1.3: a subsegment that is a Delaunay edge of no cell with a material label would be
//     lost from the mesh (every cell around it labelled outside by its circumcentre: a chord
//     of a small hole, the convex edge of a thin plate): it is split at its midpoint, down to
//     twice the terminator length, and rule P undoes a move that would lose one. Where the
//     terminator stops it (curves meeting at a small angle), the cells around it whose
//     barycentre lies in a material take that material (keepSubsegmentsInMaterial).
#include <algorithm>
#include <cmath>
#include <limits>

#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {

double RuleSetTRefiner::length(const Subsegment& s) const {
  return std::sqrt(CGAL::squared_distance(s.a->point(), s.b->point()));
}

void RuleSetTRefiner::addSegment(VH a, VH b, int curve) {
  if (a == b) return;
  const uint64_t key = pairKey(a->info().id, b->info().id);
  if (segmentOf_.count(key)) return;  // two polylines sharing a piece: one constraint
  const int index = static_cast<int>(segments_.size());
  segments_.push_back({a, b, curve, true});
  segmentOf_[key] = index;
  segmentsAt_[a->info().id].push_back(index);
  segmentsAt_[b->info().id].push_back(index);
  pushSegment(index);
}

void RuleSetTRefiner::removeSegment(int index) {
  Subsegment& s = segments_[index];
  s.alive = false;
  segmentOf_.erase(pairKey(s.a->info().id, s.b->info().id));
  for (VH v : {s.a, s.b}) {
    auto& list = segmentsAt_[v->info().id];
    list.erase(std::remove(list.begin(), list.end(), index), list.end());
  }
}

bool RuleSetTRefiner::strictlyInDiametralBall(const CgalPoint& p, const Subsegment& s) const {
  const CgalPoint m = CGAL::midpoint(s.a->point(), s.b->point());
  const double r2 = 0.25 * CGAL::squared_distance(s.a->point(), s.b->point());
  // Points on the sphere (shell splits of neighbouring segments) do not encroach.
  return CGAL::squared_distance(p, m) < r2 * (1 - 1e-9);
}

// Encroached = some vertex strictly inside the diametral ball. A subsegment that is not a
// Delaunay edge is encroached (Gabriel edges are Delaunay edges); one that is has an
// encroaching vertex among the vertices of its incident cells if any.
bool RuleSetTRefiner::encroached(const Subsegment& s) const {
  CH c;
  int i, j;
  if (!dt_.is_edge(s.a, s.b, c, i, j)) return true;
  auto circ = dt_.incident_cells(c, i, j), done = circ;
  do {
    for (int k = 0; k < 4; ++k) {
      VH v = circ->vertex(k);
      if (v == s.a || v == s.b || dt_.is_infinite(v)) continue;
      if (strictlyInDiametralBall(v->point(), s)) return true;
    }
  } while (++circ != done);
  return false;
}

bool RuleSetTRefiner::outsideEveryMaterial(const Subsegment& s) const {
  CH c;
  int i, j;
  if (!dt_.is_edge(s.a, s.b, c, i, j)) return false;
  auto circ = dt_.incident_cells(c, i, j), done = circ;
  do
    if (!dt_.is_infinite(circ) && circ->info().label > 0) return false;
  while (++circ != done);
  return true;
}

// After the last vertex move: around a subsegment that is still an edge of no labelled cell,
// the cells whose barycentre lies in a material get that material (what the barycentre
// assignment would give them), so the mesh keeps the constraint. One none of whose cells has
// its barycentre in a material stays lost; the final check counts it.
void RuleSetTRefiner::keepSubsegmentsInMaterial() {
  for (const Subsegment& s : segments_) {
    if (!s.alive || !outsideEveryMaterial(s)) continue;
    CH c;
    int i, j;
    dt_.is_edge(s.a, s.b, c, i, j);
    bool kept = false;
    auto circ = dt_.incident_cells(c, i, j), done = circ;
    do {
      if (dt_.is_infinite(circ)) continue;
      const int label = oracle_.label(barycentre(circ));
      if (label <= 0) continue;
      circ->info().label = label;
      ++stats_.cells_labelled_by_barycentre;
      kept = true;
    } while (++circ != done);
    stats_.subsegments_kept_by_barycentre += kept;
  }
}

int RuleSetTRefiner::starAt(VH v) const {
  auto it = starOfVertex_.find(v->info().id);
  return it == starOfVertex_.end() ? -1 : it->second;
}

double RuleSetTRefiner::shortestAtStar(int star) const {
  double shortest = std::numeric_limits<double>::infinity();
  for (int s : segmentsAt_[stars_[star].vertex->info().id]) shortest = std::min(shortest, length(segments_[s]));
  return shortest;
}

RuleSetTRefiner::SegmentSplit RuleSetTRefiner::badSegmentSplit(int index, bool assumeEncroached) const {
  const Subsegment& s = segments_[index];
  const double len = length(s);
  const Point3 a = toPoint3(s.a->point()), b = toPoint3(s.b->point());
  for (int end = 0; end < 2; ++end) {
    const int star = starAt(end == 0 ? s.a : s.b);
    if (star < 0) continue;
    const Point3 from = end == 0 ? a : b, to = end == 0 ? b : a;
    const double third = firstSplitRadius(stars_[star]);
    if (len > third * (1 + 1e-9)) return {"T1.1", splitPointOnCurve(s, from + (third / len) * (to - from), &from, third)};
    const double shortest = shortestAtStar(star);
    if (len > shortest * (1 + 1e-9))
      return {"T1.2 shell", splitPointOnCurve(s, from + (shortest / len) * (to - from), &from, shortest)};
  }
  if (assumeEncroached || encroached(s)) return {"T1.2", splitPointOnCurve(s, 0.5 * (a + b))};
  // The terminator bounds T1.3 as it bounds T1.2: where curves meet at 0 degrees (the nut of
  // presse_asm.step) pieces far below it are still lost, and would only add elements left.
  if (!belowTerminator(s) && outsideEveryMaterial(s)) return {"T1.3", splitPointOnCurve(s, 0.5 * (a + b))};
  return {};
}

// Where T1.1 splits the subsegments at a star vertex: l_min,i / 3 (thesis). Beyond the
// thesis, at a star whose curves meet at a small angle, at l_min,i: its pieces are split to
// equal chords (the shell rule), which never encroach each other, and the closer the first
// split to the apex the closer the pair of vertices it leaves on two tangent curves (the
// gap grows with the square of the distance): part.step's line tangent to an arc left
// pairs 0.006 mm apart at 0.55 mm, slivers of 1.2 degrees after perturbation; at 1.66 mm,
// 2.3 degrees, and 6,275 tets instead of 7,731.
double RuleSetTRefiner::firstSplitRadius(const Star& star) { return star.smallAngle ? star.lmin : star.lmin / 3; }

// The point of curve `curve` for a vertex meant at p, when options_.onto_curve knows the
// curve: with `from`, the curve point at distance `radius` from it, found by projecting
// alternately onto the curve and the sphere (the star-vertex rules compare chord lengths,
// so it must be exact); else the curve point nearest to p. p itself when the curve is
// unknown or the iteration does not settle.
Point3 RuleSetTRefiner::pointOnCurve(int curve, const Point3& p, const Point3* from, double radius) const {
  if (!options_.onto_curve || curve < 0) return p;
  Point3 q = options_.onto_curve(curve, p);
  if (from) {
    for (int k = 0; k < 20 && std::abs(distance(q, *from) - radius) > 1e-12 * radius; ++k) {
      const double d = distance(q, *from);
      if (!(d > 0)) return p;
      q = options_.onto_curve(curve, *from + (radius / d) * (q - *from));
    }
    if (!(std::abs(distance(q, *from) - radius) <= 1e-10 * radius)) return p;
  }
  return std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]) ? q : p;
}

// Where a split of s at chord point p goes (T1.1 and shells: at chord distance `radius`
// from star vertex `from`): on s's curve (pointOnCurve) if that point is strictly inside
// s's diametral ball (between the ends), else p.
Point3 RuleSetTRefiner::splitPointOnCurve(const Subsegment& s, const Point3& p, const Point3* from,
                                          double radius) const {
  const Point3 a = toPoint3(s.a->point()), b = toPoint3(s.b->point());
  const Point3 q = pointOnCurve(s.curve, p, from, radius);
  return distance(q, 0.5 * (a + b)) < 0.5 * distance(a, b) * (1 - 1e-3) ? q : p;
}

void RuleSetTRefiner::pushSegment(int index) {
  if (!segments_[index].alive) return;
  segmentQueue_.push({length(segments_[index]), static_cast<uint64_t>(index), CH(), -1});
}

// Splits subsegment `index` at `point` (a point of its chord).
bool RuleSetTRefiner::splitSegment(int index, const Point3& point, const std::string& rule) {
  const Subsegment s = segments_[index];
  Zone zone = examine(point, s.a->cell(), index);
  if (zone.duplicate) {
    unsplittable_.push_back(index);
    return false;
  }
  removeSegment(index);
  VH v = commit(zone, 1, s.curve);
  addSegment(s.a, v, s.curve);
  addSegment(v, s.b, s.curve);
  ++stats_.insertions[rule];
  return true;
}

bool RuleSetTRefiner::splitEncroached(int index, const std::string& rule) {
  const SegmentSplit split = badSegmentSplit(index, true);
  return splitSegment(index, split.point, rule);
}

bool RuleSetTRefiner::nearSmallAngle(const Subsegment& s) const {
  if (std::find(options_.small_angle_curves.begin(), options_.small_angle_curves.end(), s.curve) !=
      options_.small_angle_curves.end())
    return true;
  const Point3 mid = toPoint3(CGAL::midpoint(s.a->point(), s.b->point()));
  // A bonded wedge is where two parts rest on each other tangentially: curves of both run
  // there at an angle of nothing (a rod's end circle along the plate's edge under it).
  if (options_.criteria.bonded_wedges && options_.criteria.bonded_wedges->widthAt(mid) > 0) return true;
  const double reachOf = 4 * length(s);
  for (const Point3& p : smallAnglePoints_)
    if (distance(p, mid) < reachOf) return true;
  return false;
}

bool RuleSetTRefiner::refineOneSegment() {
  while (!segmentQueue_.empty()) {
    const QueueEntry e = segmentQueue_.top();
    segmentQueue_.pop();
    const int index = static_cast<int>(e.stamp);
    if (!segments_[index].alive) continue;
    const SegmentSplit split = badSegmentSplit(index, false);
    if (split.rule.empty()) continue;
    if (split.rule == "T1.2" && encroachmentTerminatorRefuses(index)) continue;
    if (splitSegment(index, split.point, split.rule)) return true;
  }
  return false;
}

// Terminator for T1.2 (beyond the thesis). Two curves that meet at a small angle (part.step:
// a line tangent to an arc) run within less than their sampling of each other: every
// vertex on one lies in the diametral balls of the other's subsegments, and midpoint
// splits answer each other down to any length (part.step before the l_min,i first split:
// 0.017 mm pieces, 1/400 of the edge size, each close pair of segment vertices a sliver;
// presse_asm.step's nut, whose chamfer circle touches the hexagon's flats: 0.01 mm, the
// surfaces around following; test PresseNutThesis.*). Next to a small input angle a
// subsegment shorter than twice the terminator length that is still a Delaunay edge, which
// is all the constraint needs, is left encroached; one that lost its edge is still split.
bool RuleSetTRefiner::encroachmentTerminatorRefuses(int index) {
  const Subsegment& s = segments_[index];
  if (!nearSmallAngle(s) || !belowTerminator(s)) return false;
  CH c;
  int i, j;
  if (!dt_.is_edge(s.a, s.b, c, i, j)) return false;
  // Kept out of the final sweep for encroached subsegments; an insertion that takes its
  // edge away queues it again (commit), and then it is split.
  if (std::find(unsplittable_.begin(), unsplittable_.end(), index) == unsplittable_.end()) unsplittable_.push_back(index);
  ++stats_.encroachment_refusals;  // a subsegment may be refused again
  return true;
}

// When the queues are empty: one sweep makes sure no subsegment is left encroached.
bool RuleSetTRefiner::queueBadSegments() {
  bool again = false;
  for (size_t s = 0; s < segments_.size(); ++s)
    if (segments_[s].alive && !badSegmentSplit(static_cast<int>(s), false).rule.empty() &&
        std::find(unsplittable_.begin(), unsplittable_.end(), static_cast<int>(s)) == unsplittable_.end()) {
      pushSegment(static_cast<int>(s));
      again = true;
    }
  return again;
}

}  // namespace oraclemesh::refine
