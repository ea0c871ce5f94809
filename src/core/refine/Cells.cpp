// T3 of Rule Set T (thesis §3.3.1): a cell with label > 0 is bad when its circumradius is
// above cell_size or its radius-edge ratio above the bound (CellCriteria.h): T3.1 its
// circumcentre encroaches a subsegment -> split it; T3.2 the circumcentre is in a surface
// Delaunay ball whose centre encroaches a subsegment -> split that; T3.3 the circumcentre is
// in a surface Delaunay ball -> insert that ball's centre; T3.4 insert the circumcentre.
// Beyond the thesis (which terminates only for input angles of 60 degrees and more), the
// terminator: a cell that fails only the radius-edge bound and whose circumcentre would
// split a subsegment near a small input angle is left, and no point closer than the
// terminator length to an existing vertex is inserted; every element left is listed.
// Materials go by the circumcentre (Pons et al. 2007) or the barycentre (thesis §4.1).
#include <algorithm>
#include <cmath>

#include "refine/CellCriteria.h"
#include "refine/Circumcentre.h"
#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {

void RuleSetTRefiner::evaluateCell(CH c) {
  CellInfo& info = c->info();
  info.stamp = ++stampCounter_;
  for (FacetData& f : info.facets) f.known = false;
  if (dt_.is_infinite(c)) {
    info.label = info.centreLabel = 0;
    return;
  }
  const std::array<VH, 4> corners = cornersForRounding(c);
  const Point3 middle = 0.5 * (oracle_.bbox().min + oracle_.bbox().max);
  const CgalPoint cc =
      finiteCircumcentre(corners[0]->point(), corners[1]->point(), corners[2]->point(), corners[3]->point(),
                         2 * reach_ + distance(toPoint3(corners[0]->point()), middle));
  info.circumcentre = toPoint3(cc);
  info.radius = std::sqrt(CGAL::squared_distance(cc, corners[0]->point()));
  const bool byBarycentre =
      options_.assignment == MaterialAssignment::Barycenter || (hook_ && hook_->labelsByBarycentre(c));
  // Four coplanar corners (on a planar face, or boundary points of one plane elsewhere)
  // leave the circumcentre far off. A cell labelled by its circumcentre is then outside and
  // never refined; one labelled by its barycentre may be, and such a point must never be
  // inserted.
  if (byBarycentre &&
      ((hook_ && hook_->hasUndefinedCircumsphere(c)) || !(distance(info.circumcentre, middle) < reach_)))
    useCircleCentre(c, info);
  info.centreLabel = oracle_.label(info.circumcentre);
  info.label = byBarycentre ? oracle_.label(barycentre(c)) : info.centreLabel;
}

// A cell's corners in the order its circumcentre is computed in: as stored, unless rule P
// moves vertices, after which the stored order depends on memory layout (CGAL's vertex
// removal orders by handle) and the corners go by vertex id, so the rounding (labels,
// surface ball centres) is the same in every run.
std::array<VH, 4> RuleSetTRefiner::cornersForRounding(CH c) const {
  std::array<VH, 4> corners{c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
  if (movingVertices_)
    std::sort(corners.begin(), corners.end(), [](VH x, VH y) { return x->info().id < y->info().id; });
  return corners;
}

Point3 RuleSetTRefiner::barycentre(CH c) {
  Point3 bary{0, 0, 0};
  for (int k = 0; k < 4; ++k) bary = bary + 0.25 * toPoint3(c->vertex(k)->point());
  return bary;
}

// A cell with its four corners on one planar face is flat (four cocircular points of the
// face): its circumsphere is undefined, and the circumcentre computed from rounded
// coordinates lands anywhere, or at infinity. The centre of the circle through the corners
// stands in for it: a point of the face, which splits the cocircular corners once inserted.
// (The same for any cell whose circumcentre lies beyond the bounding corners.)
void RuleSetTRefiner::useCircleCentre(CH c, CellInfo& info) const {
  int skip = 0;  // the corner left out: the other three span the largest triangle
  double largest = -1;
  for (int k = 0; k < 4; ++k) {
    const CgalPoint &a = c->vertex((k + 1) & 3)->point(), &b = c->vertex((k + 2) & 3)->point(),
                    &d = c->vertex((k + 3) & 3)->point();
    const double area = std::sqrt(CGAL::squared_area(a, b, d));
    if (area > largest) largest = area, skip = k;
  }
  const CgalPoint &a = c->vertex((skip + 1) & 3)->point(), &b = c->vertex((skip + 2) & 3)->point(),
                  &d = c->vertex((skip + 3) & 3)->point();
  const CgalPoint centre = CGAL::circumcenter(a, b, d);
  info.circumcentre = toPoint3(centre);
  info.radius = std::sqrt(CGAL::squared_distance(centre, a));
}

double RuleSetTRefiner::flatness(CH c) { return refine::flatness(cornerPoints(c)); }

double RuleSetTRefiner::shortestEdge(CH c) { return refine::shortestEdge(cornerPoints(c)); }

double RuleSetTRefiner::longestEdge(CH c) {
  double longest = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      longest = std::max(longest, distance(toPoint3(c->vertex(a)->point()), toPoint3(c->vertex(b)->point())));
  return longest;
}

// How far a cell is beyond its material's criteria (> 1: bad); 0 when good or outside.
double RuleSetTRefiner::cellBadness(CH c, bool* sizeFails, std::string* reason) const {
  if (dt_.is_infinite(c) || c->info().label <= 0) return 0;
  const int label = c->info().label;
  const MaterialCriteria& criteria = options_.criteria.of(label);
  const CellShape shape = measureCell(cornerPoints(c), c->info().radius);
  if (options_.criteria.cell_field && criteria.from_field.cell_size) {
    // Most cells meet their size by far: a lower bound of the cell field from the corners' values
    // decides those without a query at the circumcentre.
    const VH corners[4] = {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
    const double below = std::min(criteria.cell_size, fieldsBelow(c->info().circumcentre, corners, 4).cell);
    if (below > 0 && CellCriteria(criteria, below).judge(shape).badness == 0) {
      if (sizeFails) *sizeFails = false;
      return 0;
    }
  }
  const CellVerdict verdict =
      CellCriteria(criteria, options_.criteria.cellSizeAt(label, c->info().circumcentre)).judge(shape);
  if (sizeFails) *sizeFails = verdict.sizeFails;
  if (reason && verdict.badness > 0) *reason = verdict.reason;
  return verdict.badness;
}

// Whether a bad cell is refined at its circumcentre. Not so for a flat cell whose
// circumcentre lies farther than its longest edge from its corners: four (nearly) coplanar
// corners, e.g. two samples each of two parallel feature circles on a cylinder, are (nearly)
// cocircular, and their circumcentre is then anywhere on the circle's axis: rounding put
// U_Joint_2.stp's 20 mm from the cell, where T3.4 inserted a stray vertex next to a face and
// the flat cell stayed. A flat cell whose circumcentre stays near it (boundary points on a
// planar face) keeps the circumcentre and its redirections to the surface balls, which put
// the new point on the face; inserting its centroid as an interior point there instead made
// implant_in_bone (a) 31 % larger.
bool RuleSetTRefiner::refinedAtCircumcentre(CH c) const {
  if (!FlatCellCriterion::isFlat(flatness(c))) return true;
  const Point3 centre = c->info().circumcentre;
  const double longest = longestEdge(c);
  for (int k = 0; k < 4; ++k)
    if (distance(centre, toPoint3(c->vertex(k)->point())) > longest) return false;
  return true;
}

// Where a bad cell is refined: its circumcentre, or else its centroid, which lies inside the
// circle of a flat cell's corners, so inside every sphere through them: its insertion always
// removes the cell.
Point3 RuleSetTRefiner::refinementPoint(CH c, bool atCircumcentre) const {
  return atCircumcentre ? c->info().circumcentre : barycentre(c);
}

bool RuleSetTRefiner::refineOneCell() {
  while (!cellQueue_.empty()) {
    const QueueEntry e = cellQueue_.top();
    cellQueue_.pop();
    if (e.cell->info().stamp != e.stamp) continue;
    bool sizeFails = false;
    if (cellBadness(e.cell, &sizeFails) <= 0) continue;
    bool atCircumcentre = refinedAtCircumcentre(e.cell);
    Zone zone = examine(refinementPoint(e.cell, atCircumcentre), e.cell);
    // A flat cell whose circumcentre rounds onto one of its corners (presse_asm.step's screw:
    // two samples each of the two circles of a 45-degree chamfer, a planar trapezoid on the
    // cone) would be left: its centroid goes in instead.
    if (zone.duplicate && atCircumcentre && FlatCellCriterion::isFlat(flatness(e.cell))) {
      atCircumcentre = false;
      zone = examine(barycentre(e.cell), e.cell);
    }
    // Terminator: a cell that meets its size but not the radius-edge bound next to a small
    // input angle cannot be fixed by splitting the subsegments there (each split makes a
    // new bad cell); and no subsegment is split below the terminator length.
    auto refuseSplit = [&](int s, const char* rule) {
      if (!sizeFails && nearSmallAngle(segments_[s])) {
        leave("cell", std::string(rule) + " would split a subsegment next to an input angle under 60 degrees", e.stamp,
              -1);
        return true;
      }
      if (belowTerminator(segments_[s])) {
        leave("cell", std::string(rule) + " would split a subsegment below the terminator length", e.stamp, -1);
        return true;
      }
      return false;
    };
    if (zone.duplicate) {
      leave("cell", "its circumcentre is a vertex already", e.stamp, -1);
      continue;
    }
    if (zone.encroached >= 0) {  // T3.1
      if (refuseSplit(zone.encroached, "T3.1")) continue;
      if (splitEncroached(zone.encroached, "T3.1")) return requeue(cellQueue_, e);
      leave("cell", "the subsegment its circumcentre encroaches cannot be split", e.stamp, -1);
      continue;
    }
    Point3 ballCentre;
    int ballEntry = -1;
    // A flat cell with a stray circumcentre: its facets have dual edges from that point, so their
    // surface balls say nothing about the boundary: its centroid goes in directly.
    if (atCircumcentre && surfaceBallContaining(zone, ballCentre, &ballEntry)) {
      const Zone surface = examine(ballCentre, e.cell);
      if (!surface.duplicate && surface.encroached >= 0) {  // T3.2
        if (refuseSplit(surface.encroached, "T3.2")) continue;
        if (splitEncroached(surface.encroached, "T3.2")) return requeue(cellQueue_, e);
        leave("cell", "the subsegment its surface ball centre encroaches cannot be split", e.stamp, -1);
        continue;
      }
      if (!surface.duplicate && !belowTerminator(surface)) {  // T3.3
        commit(surface, 2, -1, ballEntry);
        ++stats_.insertions["T3.3"];
        return requeue(cellQueue_, e);
      }
      leave("cell", "the surface ball centre it maps to is closer than the terminator length to a vertex", e.stamp,
            -1);
      continue;
    }
    if (belowTerminator(zone)) {
      leave("cell", "its circumcentre is closer than the terminator length to a vertex", e.stamp, -1);
      continue;
    }
    commit(zone, 3, -1);  // T3.4
    ++stats_.insertions["T3.4"];
    // A cell outside its point's conflict zone (rounding, near-flat cells) is still there:
    // back into the queue, so it is refined again or listed with a reason, never dropped.
    return requeue(cellQueue_, e);
  }
  return false;
}

}  // namespace oraclemesh::refine
