// The initial point set: bounding corners, the feature polylines' points (their ends are
// corners, their inner points lie on the curves) with the polylines' pieces as constrained
// subsegments, the star vertices of Rule Set Q (thesis §3.2.1) where T1.1 splits, the job's
// initial points (thesis §4.1 adds points known beforehand to the initial point set; these
// go in as interior points), and points on every input face.
#include <algorithm>
#include <cmath>
#include <random>

#include "Error.h"
#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {

// Inner point k of a polyline, put on its curve (Rule Set Q's l_min / 3 points lie on the
// chords, and the snap moving them flattens cells): next to an end, at the same chord
// distance from it, which the star-vertex rules measure; on a polyline of three points,
// where both sides count, it stays where it is.
Point3 RuleSetTRefiner::polylinePointOnCurve(const FeaturePolyline& pl, size_t k) const {
  const size_t n = pl.points.size();
  if (n <= 3) return pl.points[k];
  if (k == 1 || k + 2 == n) {
    const Point3& end = k == 1 ? pl.points[0] : pl.points[n - 1];
    return pointOnCurve(pl.curve, pl.points[k], &end, distance(pl.points[k], end));
  }
  return pointOnCurve(pl.curve, pl.points[k]);
}

VH RuleSetTRefiner::insertOrFind(const Point3& p, int dimension, int curve, bool far) {
  const CgalPoint q = toCgal(p);
  if (dt_.dimension() == 3) {
    VH near = dt_.nearest_vertex(q, lastCell_);
    if (near != VH() && !dt_.is_infinite(near) &&
        std::sqrt(CGAL::squared_distance(near->point(), q)) <= oracle_.tolerance() * 10)
      return near;
  }
  const std::size_t before = dt_.number_of_vertices();
  VH v = dt_.insert(q, lastCell_);
  lastCell_ = v->cell();
  if (dt_.number_of_vertices() > before) setInfo(v, dimension, curve, far);
  return v;
}

// Beyond the thesis, whose star vertices are all endpoints of two or more segments (its
// segments are straight input pieces; our polylines sample curves, so their inner samples
// are not star vertices either): where exactly two curves meet and their end segments make
// an angle of 90 degrees or more, as at a B-rep vertex between a straight edge and the arc
// that continues it, no point of one end segment lies inside the diametral ball of the
// other or of a piece of it. Q1 exists only to keep segments at a star vertex from
// encroaching each other (thesis lemma 3.2.2.1), so such a vertex is split like any curve
// point (T1.2), without the l_min,i / 3 pieces that would make the mesh fine around it.
// The one vertex of a closed curve stays a star vertex, as in the thesis: without the T1.1
// splits there an evenly sampled circle is a regular polygon, cospherical with every point
// on its axis, and the slivers of such a mesh kept CGAL's perturbation busy (demo assembly:
// 3.3 s instead of 0.6 s for 8,000 tets).
bool RuleSetTRefiner::isCurveContinuation(const StarVertex& sv) const {
  if (sv.incident.size() != 2 || sv.incident[0].polyline == sv.incident[1].polyline) return false;
  Point3 direction[2];
  for (int k = 0; k < 2; ++k) {
    const auto& pts = features_.polylines[sv.incident[k].polyline].points;
    direction[k] = sv.incident[k].at_start ? pts[1] - pts[0] : pts[pts.size() - 2] - pts.back();
  }
  return dot(direction[0], direction[1]) <= 0;
}

void RuleSetTRefiner::insertInitialPoints() {
  // Bounding corners first: the triangulation is three-dimensional from the start and every
  // point the refiner inserts lies inside its hull.
  const Bbox box = oracle_.bbox();
  const double margin = oracle_.diagonal();
  for (int corner = 0; corner < 8; ++corner) {
    Point3 p;
    for (int k = 0; k < 3; ++k) p[k] = (corner >> k & 1) ? box.max[k] + margin : box.min[k] - margin;
    insertOrFind(p, 3, -1, true);
  }
  // Feature vertices: polyline ends are corners (dimension 0), inner points lie on curves.
  for (const FeaturePolyline& pl : features_.polylines) {
    std::vector<VH> chain;
    for (size_t k = 0; k < pl.points.size(); ++k) {
      const bool end = k == 0 || k + 1 == pl.points.size();
      VH v = insertOrFind(end ? pl.points[k] : polylinePointOnCurve(pl, k), end ? 0 : 1, end ? -1 : pl.curve);
      if (end) v->info().dimension = 0, v->info().curve = -1;
      chain.push_back(v);
    }
    for (size_t k = 0; k + 1 < chain.size(); ++k) pendingSegments_.push_back({chain[k], chain[k + 1], pl.curve});
  }
  int64_t seeds = static_cast<int64_t>(dt_.number_of_vertices()) - 8;
  for (const StarVertex& sv : findStarVertices(features_, 10 * oracle_.tolerance())) {
    if (isCurveContinuation(sv)) continue;
    Star star;
    star.vertex = dt_.nearest_vertex(toCgal(sv.point));
    star.lmin = sv.shortest_incident_length;
    // Angles between the curves leaving the star vertex (first segments of the polylines).
    std::vector<Point3> directions;
    for (const StarVertex::Incident& inc : sv.incident) {
      const auto& pts = features_.polylines[inc.polyline].points;
      const Point3 d = inc.at_start ? pts[1] - pts[0] : pts[pts.size() - 2] - pts.back();
      directions.push_back((1 / std::max(norm(d), 1e-300)) * d);
    }
    for (size_t a = 0; a < directions.size(); ++a)
      for (size_t b = a + 1; b < directions.size(); ++b)
        if (std::acos(std::clamp(dot(directions[a], directions[b]), -1.0, 1.0)) < M_PI / 3) star.smallAngle = true;
    starOfVertex_[star.vertex->info().id] = static_cast<int>(stars_.size());
    if (star.smallAngle) smallAnglePoints_.push_back(sv.point);
    stars_.push_back(star);
  }
  stats_.star_vertices = static_cast<int64_t>(stars_.size());
  for (const Point3& p : options_.small_angle_points) smallAnglePoints_.push_back(p);

  // The job's initial points (interior points, as the thesis' user-given seeds).
  for (const Point3& p : options_.initial_points) {
    if (!oracle_.bbox().contains(p, oracle_.diagonal()))
      throw InputError("initial_points: the point (" + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " +
                       std::to_string(p[2]) + ") lies far outside the inputs: remove it or fix its coordinates");
    insertOrFind(p, 3, -1);
  }
  for (const Subsegment& s : pendingSegments_) addSegment(s.a, s.b, s.curve);
  pendingSegments_.clear();

  // Every cell and facet gets its data once; refinement keeps it current from here on.
  for (auto c = dt_.all_cells_begin(); c != dt_.all_cells_end(); ++c) evaluateCell(c);
  for (auto c = dt_.all_cells_begin(); c != dt_.all_cells_end(); ++c) {
    for (int i = 0; i < 4; ++i)
      if (!c->info().facets[i].known) evaluateFacet(c, i);
    const double bad = cellBadness(c);
    if (bad > 0) cellQueue_.push({bad, c->info().stamp, c, -1});
  }

  // Points on every face of every input that lies on the composite boundary: exact
  // crossings of a short probe across the sample, inserted unless they encroach a
  // subsegment (the boundary there is reached by segment splits instead).
  // The samples lie on regular grids, and grid points on two faces of an edge are
  // cospherical: their Delaunay cells are flat, with circumcentres nothing can be computed
  // from. A seeded shift along the face (a tenth of the spacing) puts them in general position.
  const double probe = 1e-4 * oracle_.diagonal();
  std::mt19937 random(options_.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<CompositeCrossing> samples;
  for (const OracleEntry& entry : oracle_.entries()) {
    const double facetSize = entry.role == Role::Material ? options_.criteria.of(entry.material).facet_size
                                                          : options_.criteria.defaults.facet_size;
    for (const BoundarySample& s : entry.source->boundarySamples(2 * facetSize)) {
      Point3 shift{unit(random), unit(random), unit(random)};
      shift = shift - dot(shift, s.normal) * s.normal;
      const Point3 at = s.point + (0.1 * facetSize) * shift;
      auto crossings = oracle_.crossings(at - probe * s.normal, at + probe * s.normal);
      if (crossings.empty()) crossings = oracle_.crossings(s.point - probe * s.normal, s.point + probe * s.normal);
      if (!crossings.empty()) samples.push_back(crossings.front());
    }
  }
  for (size_t k = samples.size(); k > 1; --k) std::swap(samples[k - 1], samples[random() % k]);
  for (const CompositeCrossing& sample : samples) {
    const VH v = insertIfFree(sample.point, lastCell_, 2, -1, sample.entry);
    if (v == VH()) continue;
    lastCell_ = v->cell();
    ++seeds;
  }
  stats_.initial_points = seeds;
}

}  // namespace oraclemesh::refine
