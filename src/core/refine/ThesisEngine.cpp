// Rule Set T (thesis §3.3) on a CGAL Delaunay triangulation. This is the one translation unit
// that instantiates the refiner's triangulation: keep the CGAL types in here.
//
// Rule names follow the thesis:
//   T1   a constrained subsegment is bad: next to a star vertex and longer than l_min,i / 3
//        (T1.1: split at l_min,i / 3 from the star vertex), longer than another subsegment at
//        the same star vertex (concentric shell split, see below), or encroached (T1.2:
//        midpoint);
//   T2   a restricted facet is bad (a vertex not on the boundary, surface Delaunay ball too
//        big for facet_size / facet_distance / facet_angle): T2.1 its ball centre encroaches
//        a subsegment -> split that subsegment, T2.2 else insert the ball centre;
//   T3   a cell with label > 0 is bad (circumradius > cell_size or radius-edge ratio > bound):
//        T3.1 circumcentre encroaches a subsegment -> split it; T3.2 circumcentre in a surface
//        Delaunay ball whose centre encroaches a subsegment -> split it; T3.3 circumcentre in
//        a surface Delaunay ball -> insert that ball's centre; T3.4 insert the circumcentre.
// Beyond the thesis (which terminates only for input angles of 60 degrees and more):
//   - concentric shells (Shewchuk 1998): a subsegment at a star vertex that is longer than
//     the shortest one there is split at that shortest length from the star vertex, so all
//     splits around a star vertex happen on spheres of radius l_min,i / 3 / 2^k;
//   - terminator: a cell that fails only the radius-edge bound and whose circumcentre would
//     split a subsegment near a small input angle is left, and no point closer than the
//     terminator length to an existing vertex is inserted; every element left is listed.
// Planar faces (thesis §4.1, "planar input polygons", left unfinished there; job option
// features.planar_faces), a layer between T1 and T2:
//   TP   a triangle of the 2D Delaunay triangulation of the vertices on a planar face's plane,
//        restricted to the face (PlanarFacets.h), is no facet of the 3D triangulation:
//        TP.1 its circumcentre encroaches a subsegment -> split the subsegment (as T2.1);
//        TP.2 else insert the circumcentre if it lies on the face.
//   The 2D triangulations are rebuilt when the other queues are empty (rebuilding them after
//   every insertion would cost more than the refinement); the triangles found missing then
//   go before T2 and T3. Cells with an edge on a planar face take their material from the
//   barycentre: a flat cell on the face may have its circumcentre across the plane.
//   - rule S (see refineSlivers), once T1-T3 have converged: S.4 a point near a sliver's
//     circumcentre, S.1-S.3 its redirections as in T3.1-T3.3.
//   - rule P (see perturbSlivers), last: moves a corner of each sliver rule S left (counted
//     as "P" among the insertions, though it inserts nothing).
#include "refine/ThesisEngine.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <queue>
#include <random>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "Error.h"
#include "features/RuleSetQ.h"
#include "refine/PlanarFacets.h"
#include "mesh/Quality.h"

namespace oraclemesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = K::Point_3;

struct VertexInfo {
  int64_t id = -1;
  int dimension = 3;  // 0 star/feature end, 1 on a constrained segment, 2 on the boundary, 3 interior
  int curve = -1;     // feature curve id of a dimension-1 vertex
  bool far = false;   // one of the bounding corners that keep every point inside the hull
  // Oracle entry on whose boundary a dimension-2 vertex lies exactly (it was put at one of
  // that entry's crossings or projections), -1 when not known; the snap skips such vertices.
  int boundaryEntry = -1;
};

// What the dual Voronoi edge of a facet says about the boundary. Kept on both cells of the
// facet and recomputed whenever one of them is new.
struct FacetData {
  bool known = false;
  bool restricted = false;
  Point3 centre{};  // surface Delaunay ball centre: where the dual edge crosses the boundary
  int labelA = 0, labelB = 0;
  int entry = -1;   // the oracle entry whose boundary that crossing is on
};

struct CellInfo {
  uint64_t stamp = 0;  // 0 = not evaluated; unique per evaluation (stale queue entries)
  int label = 0;       // material by the job's assignment rule
  int centreLabel = 0; // label at the circumcentre (decides restricted facets)
  Point3 circumcentre{};
  double radius = 0;
  std::array<FacetData, 4> facets;
};

using Vb = CGAL::Triangulation_vertex_base_with_info_3<VertexInfo, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<CellInfo, K>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
// Compact location: every insertion of the refiner starts from the element it refines, which
// is next to the new point, so a hierarchy would not speed up locate, and insert_in_hole does
// not maintain one.
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;
using VH = Delaunay::Vertex_handle;
using CH = Delaunay::Cell_handle;
using Facet = Delaunay::Facet;

Point3 toPoint3(const CgalPoint& p) { return {p.x(), p.y(), p.z()}; }
CgalPoint toCgal(const Point3& p) { return CgalPoint(p[0], p[1], p[2]); }

// 6 V / l_min^3 of a cell below which it counts as flat (a regular tetrahedron has 0.71).
constexpr double kFlatCell = 1e-4;

uint64_t pairKey(int64_t a, int64_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | static_cast<uint64_t>(b);
}

struct Subsegment {
  VH a, b;
  int curve = -1;
  bool alive = true;
};

struct Star {
  VH vertex;
  double lmin = 0;        // l_min,i: shortest incident input segment
  bool smallAngle = false;
};

struct QueueEntry {
  double priority = 0;
  uint64_t stamp = 0;  // for cells / facets: the cell's stamp; for segments: its index
  CH cell;
  int facet = -1;
  bool operator<(const QueueEntry& o) const {
    // Worst first; ties by stamp (insertion order) keep the run deterministic.
    return priority != o.priority ? priority < o.priority : stamp > o.stamp;
  }
};

// The result of looking at the conflict zone of a point before inserting it.
struct Zone {
  CgalPoint point;
  std::vector<CH> cells;
  Facet boundaryFacet;
  std::vector<int> segments;  // alive subsegments that are edges of conflict cells
  int encroached = -1;        // a subsegment whose diametral ball contains the point
  double insertionRadius = 0; // distance to the nearest existing vertex
  bool duplicate = false;
};

class RuleSetTRefiner {
 public:
  RuleSetTRefiner(const HierarchicalOracle& oracle, const FeatureGraph& features, const RuleSetTOptions& options,
                  const RunControl& control, RuleSetTStatistics& stats)
      : oracle_(oracle), features_(features), options_(options), control_(control), stats_(stats) {
    const double diag = oracle.diagonal();
    reach_ = 4 * diag;
    double smallest = std::numeric_limits<double>::infinity();
    auto consider = [&](const MaterialCriteria& c) {
      for (double v : {c.cell_size, c.facet_size, c.edge_size})
        if (v > 0) smallest = std::min(smallest, v);
    };
    consider(options.criteria.defaults);
    for (const auto& [m, c] : options.criteria.per_material) consider(c);
    if (!std::isfinite(smallest)) smallest = diag / 15;
    // Below this no point goes in (terminator): 1/32 of the finest size asked for.
    terminatorLength_ = smallest / 32;
  }

  TetMesh run() {
    auto t0 = std::chrono::steady_clock::now();
    auto phase = [&](const std::string& name) {
      const auto now = std::chrono::steady_clock::now();
      stats_.seconds[name] += std::chrono::duration<double>(now - t0).count();
      t0 = now;
    };
    try {
      control_.report("initial points", 0);
      insertInitialPoints();
      phase("initial_points");
      control_.report("refine", 0);
      refine();
      refineSlivers();
    } catch (const LimitError&) {
      stats_.partial = extract();
      throw;
    }
    phase("refine");
    if (!options_.planar_faces.empty()) {
      finalPlanarCheck();
      phase("planar_check");
    }
    // The elements left are Rule Set T's; the vertex moves after it aim at dihedral angles
    // only (like CGAL's perturbation, which ran after the engine before them).
    listLeftElements();
    perturbSlivers();
    phase("vertex_moves");
    TetMesh mesh = extract();
    listLeftSlivers();
    phase("extract");
    finalCheck();
    return mesh;
  }

 private:
  // ---------------------------------------------------------------- vertices and segments
  void setInfo(VH v, int dimension, int curve, bool far = false) {
    v->info().id = nextVertexId_++;
    v->info().dimension = dimension;
    v->info().curve = curve;
    v->info().far = far;
    segmentsAt_.emplace_back();
    notePlanarFaces(v);
  }

  double length(const Subsegment& s) const { return std::sqrt(CGAL::squared_distance(s.a->point(), s.b->point())); }

  void addSegment(VH a, VH b, int curve) {
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

  void removeSegment(int index) {
    Subsegment& s = segments_[index];
    s.alive = false;
    segmentOf_.erase(pairKey(s.a->info().id, s.b->info().id));
    for (VH v : {s.a, s.b}) {
      auto& list = segmentsAt_[v->info().id];
      list.erase(std::remove(list.begin(), list.end(), index), list.end());
    }
  }

  bool strictlyInDiametralBall(const CgalPoint& p, const Subsegment& s) const {
    const CgalPoint m = CGAL::midpoint(s.a->point(), s.b->point());
    const double r2 = 0.25 * CGAL::squared_distance(s.a->point(), s.b->point());
    // Points on the sphere (shell splits of neighbouring segments) do not encroach.
    return CGAL::squared_distance(p, m) < r2 * (1 - 1e-9);
  }

  // Encroached = some vertex strictly inside the diametral ball. A subsegment that is not a
  // Delaunay edge is encroached (Gabriel edges are Delaunay edges); one that is has an
  // encroaching vertex among the vertices of its incident cells if any.
  bool encroached(const Subsegment& s) const {
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

  int starAt(VH v) const {
    auto it = starOfVertex_.find(v->info().id);
    return it == starOfVertex_.end() ? -1 : it->second;
  }

  double shortestAtStar(int star) const {
    double shortest = std::numeric_limits<double>::infinity();
    for (int s : segmentsAt_[stars_[star].vertex->info().id]) shortest = std::min(shortest, length(segments_[s]));
    return shortest;
  }

  // T1: where a bad subsegment is split, and under which rule; nullopt-like (rule empty)
  // when the subsegment is good.
  struct SegmentSplit {
    std::string rule;
    Point3 point{};
  };
  SegmentSplit badSegmentSplit(int index, bool assumeEncroached) const {
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
    return {};
  }

  // Where T1.1 splits the subsegments at a star vertex: l_min,i / 3 (thesis). Beyond the
  // thesis, at a star whose curves meet at a small angle, at l_min,i: its pieces are split to
  // equal chords (the shell rule), which never encroach each other, and the closer the first
  // split to the apex the closer the pair of vertices it leaves on two tangent curves (the
  // gap grows with the square of the distance): part.step's line tangent to an arc left
  // pairs 0.006 mm apart at 0.55 mm, slivers of 1.2 degrees after perturbation; at 1.66 mm,
  // 2.3 degrees, and 6,275 tets instead of 7,731.
  static double firstSplitRadius(const Star& star) { return star.smallAngle ? star.lmin : star.lmin / 3; }

  // The point of curve `curve` for a vertex meant at p, when options_.onto_curve knows the
  // curve: with `from`, the curve point at distance `radius` from it, found by projecting
  // alternately onto the curve and the sphere (the star-vertex rules compare chord lengths,
  // so it must be exact); else the curve point nearest to p. p itself when the curve is
  // unknown or the iteration does not settle.
  Point3 pointOnCurve(int curve, const Point3& p, const Point3* from = nullptr, double radius = 0) const {
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
  Point3 splitPointOnCurve(const Subsegment& s, const Point3& p, const Point3* from = nullptr, double radius = 0) const {
    const Point3 a = toPoint3(s.a->point()), b = toPoint3(s.b->point());
    const Point3 q = pointOnCurve(s.curve, p, from, radius);
    return distance(q, 0.5 * (a + b)) < 0.5 * distance(a, b) * (1 - 1e-3) ? q : p;
  }

  void pushSegment(int index) {
    if (!segments_[index].alive) return;
    segmentQueue_.push({length(segments_[index]), static_cast<uint64_t>(index), CH(), -1});
  }

  // ------------------------------------------------------------------ cells and facets
  int labelOf(const Point3& p) const { return oracle_.label(p); }

  void evaluateCell(CH c) {
    CellInfo& info = c->info();
    info.stamp = ++stampCounter_;
    for (FacetData& f : info.facets) f.known = false;
    if (dt_.is_infinite(c)) {
      info.label = info.centreLabel = 0;
      return;
    }
    const std::array<VH, 4> corners = cornersForRounding(c);
    const CgalPoint cc =
        CGAL::circumcenter(corners[0]->point(), corners[1]->point(), corners[2]->point(), corners[3]->point());
    info.circumcentre = toPoint3(cc);
    info.radius = std::sqrt(CGAL::squared_distance(cc, corners[0]->point()));
    const bool byBarycentre = options_.assignment == MaterialAssignment::Barycenter || hasEdgeOnPlanarFace(c);
    // Four coplanar corners (on a planar face, or boundary points of one plane elsewhere)
    // leave the circumcentre at infinity or far off. A cell labelled by its circumcentre is
    // then outside and never refined; one labelled by its barycentre may be, and such a
    // point must never be inserted.
    const Point3 middle = 0.5 * (oracle_.bbox().min + oracle_.bbox().max);
    if (byBarycentre && (planarFaceOfCell(c) >= 0 || !(distance(info.circumcentre, middle) < reach_)))
      useCircleCentre(c, info);
    info.centreLabel = labelOf(info.circumcentre);
    info.label = byBarycentre ? labelOf(barycentre(c)) : info.centreLabel;
  }

  // A cell's corners in the order its circumcentre is computed in: as stored, unless rule P
  // moves vertices, after which the stored order depends on memory layout (CGAL's vertex
  // removal orders by handle) and the corners go by vertex id, so the rounding (labels,
  // surface ball centres) is the same in every run.
  std::array<VH, 4> cornersForRounding(CH c) const {
    std::array<VH, 4> corners{c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
    if (movingVertices_)
      std::sort(corners.begin(), corners.end(), [](VH x, VH y) { return x->info().id < y->info().id; });
    return corners;
  }

  static Point3 barycentre(CH c) {
    Point3 bary{0, 0, 0};
    for (int k = 0; k < 4; ++k) bary = bary + 0.25 * toPoint3(c->vertex(k)->point());
    return bary;
  }

  // The dual Voronoi edge of facet (c, i): circumcentre to circumcentre, or a ray from the
  // finite cell's circumcentre through the facet's outside, clipped far outside the domain.
  void dualOf(CH c, int i, Point3& from, Point3& to, int& labelFrom, int& labelTo) const {
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

  void evaluateFacet(CH c, int i) {
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
      }
    }
    c->info().facets[i] = data;
    n->info().facets[j] = data;
    if (data.restricted) {
      const double priority = facetBadness(c, i);
      if (priority > 0) facetQueue_.push({priority, c->info().stamp, c, i});
    }
  }

  // Smallest positive-material bound on either side of a restricted facet.
  double facetBound(const FacetData& f, double MaterialCriteria::*field) const {
    double bound = std::numeric_limits<double>::infinity();
    for (int m : {f.labelA, f.labelB})
      if (m > 0) bound = std::min(bound, options_.criteria.of(m).*field);
    return bound;
  }

  // How far a restricted facet is beyond its criteria (> 1: bad); 0 when good.
  double facetBadness(CH c, int i, std::string* reason = nullptr, bool withAngle = true) const {
    const FacetData& f = c->info().facets[i];
    if (!f.restricted) return 0;
    std::array<VH, 3> v{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
    for (VH w : v)
      if (dt_.is_infinite(w) || w->info().dimension == 3) {
        if (reason) *reason = "a vertex not on the boundary";
        return 1e6;
      }
    const CgalPoint centre = toCgal(f.centre);
    const double r = std::sqrt(CGAL::squared_distance(centre, v[0]->point()));
    double worst = 0;
    const double size = facetBound(f, &MaterialCriteria::facet_size);
    if (size > 0 && r > size) {
      worst = r / size;
      if (reason) *reason = "surface Delaunay ball radius above facet_size";
    }
    const double dist = facetBound(f, &MaterialCriteria::facet_distance);
    if (dist > 0) {
      const CgalPoint fc = CGAL::circumcenter(v[0]->point(), v[1]->point(), v[2]->point());
      const double d = std::sqrt(CGAL::squared_distance(fc, centre));
      if (d > dist && d / dist > worst) {
        worst = d / dist;
        if (reason) *reason = "facet distance above facet_distance";
      }
    }
    // Mesh_3 caps the facet angle bound at 30 degrees, where surface refinement still terminates.
    double angleBound = std::numeric_limits<double>::infinity();
    for (int m : {f.labelA, f.labelB})
      if (m > 0) angleBound = std::min(angleBound, options_.criteria.of(m).facet_angle);
    angleBound = std::min(angleBound, 30.0);
    if (withAngle && angleBound > 0 && std::isfinite(angleBound)) {
      double minAngle = 180;
      for (int k = 0; k < 3; ++k) {
        const K::Vector_3 e1 = v[(k + 1) % 3]->point() - v[k]->point();
        const K::Vector_3 e2 = v[(k + 2) % 3]->point() - v[k]->point();
        const double cosine = CGAL::scalar_product(e1, e2) / std::sqrt(e1.squared_length() * e2.squared_length());
        minAngle = std::min(minAngle, std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / M_PI);
      }
      if (minAngle < angleBound && angleBound / std::max(minAngle, 1e-9) > worst) {
        worst = angleBound / std::max(minAngle, 1e-9);
        if (reason) *reason = "facet angle below facet_angle";
      }
    }
    return worst > 1 ? worst : 0;
  }

  // 6 V / l_min^3 (0.71 for a regular tetrahedron, 0 for four coplanar corners).
  double flatness(CH c) const {
    const double shortest = shortestEdge(c);
    return 6 * std::abs(CGAL::volume(c->vertex(0)->point(), c->vertex(1)->point(), c->vertex(2)->point(),
                                     c->vertex(3)->point())) /
           (shortest * shortest * shortest);
  }

  double shortestEdge(CH c) const {
    double shortest = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        shortest = std::min(shortest, CGAL::squared_distance(c->vertex(a)->point(), c->vertex(b)->point()));
    return std::sqrt(shortest);
  }

  // How far a cell is beyond its material's criteria (> 1: bad); 0 when good or outside.
  double cellBadness(CH c, bool* sizeFails = nullptr, std::string* reason = nullptr) const {
    if (dt_.is_infinite(c) || c->info().label <= 0) return 0;
    const MaterialCriteria& crit = options_.criteria.of(c->info().label);
    const double r = c->info().radius;
    double worst = 0;
    if (sizeFails) *sizeFails = false;
    if (crit.cell_size > 0 && r > crit.cell_size) {
      worst = r / crit.cell_size;
      if (sizeFails) *sizeFails = true;
      if (reason) *reason = "circumradius above cell_size";
    }
    const double shortest = shortestEdge(c);
    // Beyond the thesis: a cell whose four corners are (all but) coplanar, as boundary points
    // placed symmetrically on two faces of a concave edge make them, has a fine radius-edge
    // ratio but no volume, and no vertex move after refinement can open it. A point goes in
    // like for any bad cell (with the same redirections), see refinementPoint.
    if (flatness(c) < kFlatCell) {
      worst = std::max(worst, 1e3);
      if (sizeFails) *sizeFails = true;
      if (reason) *reason = "flat cell (four nearly coplanar corners)";
    }
    if (crit.cell_radius_edge_ratio > 0) {
      const double ratio = r / shortest / crit.cell_radius_edge_ratio;
      if (ratio > 1 && ratio > worst) {
        worst = ratio;
        if (reason) *reason = "radius-edge ratio above cell_radius_edge_ratio";
      }
    }
    return worst > 1 ? worst : 0;
  }

  // ------------------------------------------------------------------------- insertion
  Zone examine(const Point3& p, CH hint, int splitting = -1) const {
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

  // boundaryEntry: the oracle entry on whose boundary zone.point lies exactly, if known.
  VH commit(const Zone& zone, int dimension, int curve, int boundaryEntry = -1) {
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

  void afterInsertion(VH v) {
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

  // Splits subsegment `index` at `point` (a point of its chord).
  bool splitSegment(int index, const Point3& point, const std::string& rule) {
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

  // A redirection of T2.1 / T3.1 / T3.2 to subsegment `index`: the T1 rule decides where it
  // is split (star rules first, else the midpoint).
  bool splitEncroached(int index, const std::string& rule) {
    const SegmentSplit split = badSegmentSplit(index, true);
    return splitSegment(index, split.point, rule);
  }

  bool nearSmallAngle(const Subsegment& s) const {
    if (std::find(options_.small_angle_curves.begin(), options_.small_angle_curves.end(), s.curve) !=
        options_.small_angle_curves.end())
      return true;
    const Point3 mid = toPoint3(CGAL::midpoint(s.a->point(), s.b->point()));
    const double reachOf = 4 * length(s);
    for (const Point3& p : smallAnglePoints_)
      if (distance(p, mid) < reachOf) return true;
    return false;
  }

  // -------------------------------------------------------------------- initial points
  // Inner point k of a polyline, put on its curve (Rule Set Q's l_min / 3 points lie on the
  // chords, and the snap moving them flattens cells): next to an end, at the same chord
  // distance from it, which the star-vertex rules measure; on a polyline of three points,
  // where both sides count, it stays where it is.
  Point3 polylinePointOnCurve(const FeaturePolyline& pl, size_t k) const {
    const size_t n = pl.points.size();
    if (n <= 3) return pl.points[k];
    if (k == 1 || k + 2 == n) {
      const Point3& end = k == 1 ? pl.points[0] : pl.points[n - 1];
      return pointOnCurve(pl.curve, pl.points[k], &end, distance(pl.points[k], end));
    }
    return pointOnCurve(pl.curve, pl.points[k]);
  }

  VH insertOrFind(const Point3& p, int dimension, int curve, bool far = false) {
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
  bool isCurveContinuation(const StarVertex& sv) const {
    if (sv.incident.size() != 2 || sv.incident[0].polyline == sv.incident[1].polyline) return false;
    Point3 direction[2];
    for (int k = 0; k < 2; ++k) {
      const auto& pts = features_.polylines[sv.incident[k].polyline].points;
      direction[k] = sv.incident[k].at_start ? pts[1] - pts[0] : pts[pts.size() - 2] - pts.back();
    }
    return dot(direction[0], direction[1]) <= 0;
  }

  void insertInitialPoints() {
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
      const Zone zone = examine(sample.point, lastCell_);
      if (zone.duplicate || zone.encroached >= 0 || zone.insertionRadius < terminatorLength_) continue;
      VH v = commit(zone, 2, -1, sample.entry);
      lastCell_ = v->cell();
      ++seeds;
    }
    stats_.initial_points = seeds;
  }

  // ------------------------------------------------------------------------ refinement
  void leave(const std::string& kind, const std::string& reason, uint64_t stamp, int facet) {
    leftReasons_[{stamp, facet}] = kind + ": " + reason;
  }

  // A redirection inserts another point than the element's own, which may leave the element
  // in place: it goes back into its queue (and is dropped there once it is gone or good).
  static bool requeue(std::priority_queue<QueueEntry>& queue, const QueueEntry& e) {
    if (e.cell->info().stamp == e.stamp) queue.push(e);
    return true;
  }

  bool refineOneSegment() {
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
  bool encroachmentTerminatorRefuses(int index) {
    const Subsegment& s = segments_[index];
    if (!nearSmallAngle(s) || length(s) / 2 >= terminatorLength_) return false;
    CH c;
    int i, j;
    if (!dt_.is_edge(s.a, s.b, c, i, j)) return false;
    // Kept out of the final sweep for encroached subsegments; an insertion that takes its
    // edge away queues it again (commit), and then it is split.
    if (std::find(unsplittable_.begin(), unsplittable_.end(), index) == unsplittable_.end()) unsplittable_.push_back(index);
    ++stats_.insertions["T1.2 left encroached"];  // refusals (a subsegment may be refused again)
    return true;
  }

  bool refineOneFacet() {
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
        if (length(segments_[zone.encroached]) / 2 < terminatorLength_) {
          leave("facet", "its ball centre encroaches a subsegment shorter than the terminator length", e.stamp, e.facet);
          continue;
        }
        if (splitEncroached(zone.encroached, "T2.1")) return requeue(facetQueue_, e);
        leave("facet", "the subsegment its ball centre encroaches cannot be split", e.stamp, e.facet);
        continue;
      }
      if (zone.insertionRadius < terminatorLength_) {
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
  bool facetAngleTerminatorRefuses(const QueueEntry& e, int s) {
    if (!nearSmallAngle(segments_[s]) || facetBadness(e.cell, e.facet, nullptr, false) > 0) return false;
    leave("facet", "T2.1 would split a subsegment next to an input angle under 60 degrees for the facet angle alone",
          e.stamp, e.facet);
    return true;
  }

  // The surface Delaunay ball of a restricted facet of the conflict zone that contains p.
  // entry (if given): the oracle entry whose boundary the centre is on.
  bool surfaceBallContaining(const Zone& zone, Point3& centre, int* entry = nullptr) const {
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

  // Whether a bad cell is refined at its circumcentre. Not so for a flat cell whose
  // circumcentre lies farther than its longest edge from its corners: four (nearly) coplanar
  // corners, e.g. two samples each of two parallel feature circles on a cylinder, are (nearly)
  // cocircular, and their circumcentre is then anywhere on the circle's axis: rounding put
  // U_Joint_2.stp's 20 mm from the cell, where T3.4 inserted a stray vertex next to a face and
  // the flat cell stayed. A flat cell whose circumcentre stays near it (boundary points on a
  // planar face) keeps the circumcentre and its redirections to the surface balls, which put
  // the new point on the face; inserting its centroid as an interior point there instead made
  // implant_in_bone (a) 31 % larger.
  bool refinedAtCircumcentre(CH c) const {
    if (flatness(c) >= kFlatCell) return true;
    const Point3 centre = c->info().circumcentre;
    const double longest = longestEdge(c);
    for (int k = 0; k < 4; ++k)
      if (distance(centre, toPoint3(c->vertex(k)->point())) > longest) return false;
    return true;
  }

  // Where a bad cell is refined: its circumcentre, or else its centroid, which lies inside the
  // circle of a flat cell's corners, so inside every sphere through them: its insertion always
  // removes the cell.
  Point3 refinementPoint(CH c, bool atCircumcentre) const {
    return atCircumcentre ? c->info().circumcentre : barycentre(c);
  }

  double longestEdge(CH c) const {
    double longest = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        longest = std::max(longest, distance(toPoint3(c->vertex(a)->point()), toPoint3(c->vertex(b)->point())));
    return longest;
  }

  bool refineOneCell() {
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
      if (zone.duplicate && atCircumcentre && flatness(e.cell) < kFlatCell) {
        atCircumcentre = false;
        zone = examine(barycentre(e.cell), e.cell);
      }
      // Terminator: a cell that meets its size but not the radius-edge bound next to a small
      // input angle cannot be fixed by splitting the subsegments there (each split makes a
      // new bad cell); and no subsegment is split below the terminator length.
      auto refuseSplit = [&](int s, const char* rule) {
        if (!sizeFails && nearSmallAngle(segments_[s])) {
          leave("cell", std::string(rule) + " would split a subsegment next to an input angle under 60 degrees",
                e.stamp, -1);
          return true;
        }
        if (length(segments_[s]) / 2 < terminatorLength_) {
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
        if (!surface.duplicate && surface.insertionRadius >= terminatorLength_) {  // T3.3
          commit(surface, 2, -1, ballEntry);
          ++stats_.insertions["T3.3"];
          return requeue(cellQueue_, e);
        }
        leave("cell", "the surface ball centre it maps to is closer than the terminator length to a vertex", e.stamp,
              -1);
        continue;
      }
      if (zone.insertionRadius < terminatorLength_) {
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

  void refine() {
    int64_t steps = 0;
    const double expected = options_.max_vertices > 0 ? static_cast<double>(options_.max_vertices) / 20 : 1e5;
    while (true) {
      if ((++steps & 63) == 0) {
        control_.checkpoint();
        if ((steps & 4095) == 0) control_.report("refine", std::min(0.99, dt_.number_of_vertices() / expected));
      }
      if (refineOneSegment() || refineOnePlanarTriangle() || refineOneFacet() || refineOneCell()) continue;
      // The queues are empty: one sweep makes sure no subsegment is left encroached.
      bool again = false;
      for (size_t s = 0; s < segments_.size(); ++s)
        if (segments_[s].alive && !badSegmentSplit(static_cast<int>(s), false).rule.empty() &&
            std::find(unsplittable_.begin(), unsplittable_.end(), static_cast<int>(s)) == unsplittable_.end()) {
          pushSegment(static_cast<int>(s));
          again = true;
        }
      if (!again) again = queueMissingPlanarTriangles();
      if (!again) break;
    }
  }

  // ------------------------------------------------------- planar faces (thesis §4.1)
  // Records on which planar faces' planes a new vertex lies (within the oracle tolerance:
  // exact crossings, splits of straight segments and circumcentres put there all do).
  void notePlanarFaces(VH v) {
    if (options_.planar_faces.empty()) return;
    planarVertices_.resize(options_.planar_faces.size());
    planarFacesOfVertex_.resize(static_cast<size_t>(nextVertexId_));
    if (v->info().far) return;
    const Point3 p = toPoint3(v->point());
    for (size_t f = 0; f < options_.planar_faces.size(); ++f) {
      const PlanarFace& face = options_.planar_faces[f];
      if (!face.box.contains(p) || std::abs(face.height(p)) > oracle_.tolerance()) continue;
      planarVertices_[f].push_back(v);
      planarFacesOfVertex_[v->info().id].push_back(static_cast<int>(f));
    }
  }

  bool hasEdgeOnPlanarFace(CH c) const {
    if (planarFacesOfVertex_.empty()) return false;
    for (int a = 0; a < 4; ++a) {
      if (dt_.is_infinite(c->vertex(a))) return false;
      const auto& fa = planarFacesOfVertex_[c->vertex(a)->info().id];
      if (fa.empty()) continue;
      for (int b = a + 1; b < 4; ++b) {
        if (dt_.is_infinite(c->vertex(b))) return false;
        for (int f : planarFacesOfVertex_[c->vertex(b)->info().id])
          if (std::find(fa.begin(), fa.end(), f) != fa.end()) return true;
      }
    }
    return false;
  }

  // The planar face all four corners of a cell lie on, or -1.
  int planarFaceOfCell(CH c) const {
    if (planarFacesOfVertex_.empty()) return -1;
    for (int k = 0; k < 4; ++k)
      if (dt_.is_infinite(c->vertex(k))) return -1;
    for (int f : planarFacesOfVertex_[c->vertex(0)->info().id]) {
      bool all = true;
      for (int k = 1; k < 4 && all; ++k) {
        const auto& faces = planarFacesOfVertex_[c->vertex(k)->info().id];
        all = std::find(faces.begin(), faces.end(), f) != faces.end();
      }
      if (all) return f;
    }
    return -1;
  }

  // A cell with its four corners on one planar face is flat (four cocircular points of the
  // face): its circumsphere is undefined, and the circumcentre computed from rounded
  // coordinates lands anywhere, or at infinity. The centre of the circle through the corners
  // stands in for it: a point of the face, which splits the cocircular corners once inserted.
  // (The same for any cell whose circumcentre lies beyond the bounding corners.)
  void useCircleCentre(CH c, CellInfo& info) const {
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

  struct QueuedPlanarTriangle {
    int face = -1;
    std::array<VH, 3> corners;
    Point3 circumcentre{};
    double radius = 0;
    size_t pointsAtCheck = 0;  // vertices on the face when the triangle was found
    CH flatCell;               // set for a flat cell on the face (its circle centre goes in)
    uint64_t flatStamp = 0;
  };

  static std::array<int64_t, 3> cornerKey(const std::array<VH, 3>& corners) {
    std::array<int64_t, 3> key{corners[0]->info().id, corners[1]->info().id, corners[2]->info().id};
    std::sort(key.begin(), key.end());
    return key;
  }

  bool isFacet(const std::array<VH, 3>& corners) const {
    CH c;
    int i, j, k;
    return dt_.is_facet(corners[0], corners[1], corners[2], c, i, j, k);
  }

  // The restricted 2D Delaunay triangles of face f; only those that are no 3D facet when
  // `missingOnly`.
  std::vector<QueuedPlanarTriangle> planarTriangles(size_t f, bool missingOnly) const {
    const std::vector<VH>& vertices = planarVertices_[f];
    std::vector<Point3> points;
    points.reserve(vertices.size());
    for (VH v : vertices) points.push_back(toPoint3(v->point()));
    auto cornersOf = [&](const std::array<int, 3>& t) {
      return std::array<VH, 3>{vertices[t[0]], vertices[t[1]], vertices[t[2]]};
    };
    std::function<bool(const std::array<int, 3>&)> wanted;
    if (missingOnly) wanted = [&](const std::array<int, 3>& t) { return !isFacet(cornersOf(t)); };
    std::vector<QueuedPlanarTriangle> result;
    for (const PlanarTriangle& t : restrictedPlanarTriangles(options_.planar_faces[f], points, oracle_, wanted))
      result.push_back({static_cast<int>(f), cornersOf(t.corners), t.circumcentre, t.radius, vertices.size()});
    return result;
  }

  // At a fixpoint of the other rules: queues the planar triangles the 3D triangulation lacks.
  // True when there are some and the triangulation changed since the last look (otherwise
  // the answer, and what the layer can do about it, are the same as last time).
  bool queueMissingPlanarTriangles() {
    if (options_.planar_faces.empty()) return false;
    const int64_t vertices = static_cast<int64_t>(dt_.number_of_vertices());
    if (vertices == verticesAtPlanarCheck_) return false;
    verticesAtPlanarCheck_ = vertices;
    planarQueue_.clear();
    for (size_t f = 0; f < options_.planar_faces.size(); ++f) {
      std::vector<QueuedPlanarTriangle> missing = planarTriangles(f, true);
      planarQueue_.insert(planarQueue_.end(), missing.begin(), missing.end());
    }
    if (!planarChecked_) stats_.planar.missing_at_first_check = static_cast<int64_t>(planarQueue_.size());
    planarChecked_ = true;
    // Flat cells on a face whatever their label (one labelled outside between two materials
    // would be a gap of no thickness in the interface).
    for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
      const int f = planarFaceOfCell(c);
      if (f < 0) continue;
      QueuedPlanarTriangle flat;
      flat.face = f;
      flat.corners = {c->vertex(0), c->vertex(1), c->vertex(2)};
      flat.circumcentre = c->info().circumcentre;
      flat.radius = c->info().radius;
      flat.pointsAtCheck = planarVertices_[f].size();
      flat.flatCell = c;
      flat.flatStamp = c->info().stamp;
      planarQueue_.push_back(flat);
    }
    // Popped from the back: the largest circumradius first; ties in a stable order.
    std::stable_sort(planarQueue_.begin(), planarQueue_.end(),
                     [](const QueuedPlanarTriangle& a, const QueuedPlanarTriangle& b) { return a.radius < b.radius; });
    return !planarQueue_.empty();
  }

  // A vertex put on the face since the triangle was found lies inside its circumcircle: the
  // triangle is no longer one of the face's 2D Delaunay triangles.
  bool planarTriangleGone(const QueuedPlanarTriangle& t) const {
    const std::vector<VH>& vertices = planarVertices_[t.face];
    for (size_t k = t.pointsAtCheck; k < vertices.size(); ++k)
      if (distance(toPoint3(vertices[k]->point()), t.circumcentre) < t.radius * (1 - 1e-9)) return true;
    return false;
  }

  bool refineOnePlanarTriangle() {
    while (!planarQueue_.empty()) {
      const QueuedPlanarTriangle t = planarQueue_.back();
      planarQueue_.pop_back();
      if (t.flatCell != CH() ? t.flatCell->info().stamp != t.flatStamp : isFacet(t.corners)) continue;
      if (planarTriangleGone(t)) continue;
      auto leaveTriangle = [&](const std::string& why) { planarLeft_[cornerKey(t.corners)] = why; };
      if (t.radius < terminatorLength_) {
        leaveTriangle("its circumradius is below the terminator length");
        continue;
      }
      const Zone zone = examine(t.circumcentre, t.corners[0]->cell());
      if (zone.duplicate) {
        leaveTriangle("its circumcentre is a vertex already");
        continue;
      }
      if (zone.encroached >= 0) {  // TP.1
        if (length(segments_[zone.encroached]) / 2 < terminatorLength_) {
          leaveTriangle("its circumcentre encroaches a subsegment shorter than the terminator length");
          continue;
        }
        if (splitEncroached(zone.encroached, "TP.1")) {
          ++stats_.planar.insertions;
          return true;
        }
        leaveTriangle("the subsegment its circumcentre encroaches cannot be split");
        continue;
      }
      // Only a point of the face itself goes in, exactly where the oracle puts the face.
      Point3 onFace;
      if (!onCompositeFace(options_.planar_faces[t.face], t.circumcentre, oracle_, &onFace)) {
        leaveTriangle("its circumcentre lies off the face's part of the composite boundary");
        continue;
      }
      const Zone exact = examine(onFace, t.corners[0]->cell());
      if (exact.duplicate || exact.encroached >= 0 || exact.insertionRadius < terminatorLength_) {
        leaveTriangle("its circumcentre is closer than the terminator length to a vertex");
        continue;
      }
      commit(exact, 2, -1, options_.planar_faces[t.face].entry);  // TP.2
      ++stats_.insertions["TP.2"];
      ++stats_.planar.insertions;
      return true;
    }
    return false;
  }

  void finalPlanarCheck() {
    constexpr size_t kListed = 200;
    PlanarFaceStatistics& s = stats_.planar;
    s.faces = s.triangles = s.missing = 0;
    s.missing_triangles.clear();
    for (size_t f = 0; f < options_.planar_faces.size(); ++f) {
      const std::vector<QueuedPlanarTriangle> triangles = planarTriangles(f, false);
      if (triangles.empty()) continue;
      ++s.faces;
      s.triangles += static_cast<int64_t>(triangles.size());
      for (const QueuedPlanarTriangle& t : triangles) {
        if (isFacet(t.corners)) continue;
        ++s.missing;
        if (s.missing_triangles.size() >= kListed) continue;
        const PlanarFace& face = options_.planar_faces[f];
        auto why = planarLeft_.find(cornerKey(t.corners));
        s.missing_triangles.push_back({face.entry, face.face, t.circumcentre, t.radius,
                                       why != planarLeft_.end() ? why->second : "not refined"});
      }
    }
  }

  // ------------------------------------------------------- S: slivers (beyond the thesis)
  // Rule Set T bounds radius-edge ratios, which slivers meet. Rule S gives each cell inside
  // the materials whose smallest dihedral angle is under options_.sliver_dihedral_deg a point
  // near its circumcentre: the best of a few seeded points in the ball of radius
  // kSliverPickRadius x circumradius around it, judged by the smallest dihedral angle of the
  // cells the point would make (random point placement, Chew 1997, Li & Teng 2001). Points in
  // that ball lie inside the sliver's circumsphere, so any of them destroys the sliver. A
  // candidate that encroaches a subsegment or lies in a surface Delaunay ball is not inserted;
  // when no candidate qualifies, the circumcentre is redirected as in T3 (S.1 splits the
  // subsegment it encroaches, S.2 the one its surface ball centre encroaches, S.3 inserts that
  // ball centre) so segments and restricted facets keep their guarantees. Each round gives
  // every sliver one try and T1-T3 then repair what the insertions broke; after kSliverRounds
  // the slivers left are listed.
  static constexpr int kSliverRounds = 4;
  static constexpr int kSliverCandidates = 12;
  static constexpr double kSliverPickRadius = 0.4;

  static double minDihedralDeg(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
    const std::array<double, 6> angles = dihedralAngles(a, b, c, d);
    return *std::min_element(angles.begin(), angles.end());
  }

  double minDihedralDeg(CH c) const {
    return minDihedralDeg(toPoint3(c->vertex(0)->point()), toPoint3(c->vertex(1)->point()),
                          toPoint3(c->vertex(2)->point()), toPoint3(c->vertex(3)->point()));
  }

  // Rule S scans every cell each round. Most are far from the bound, and the cosine of the
  // smallest angle (no trig) settles those; only cells near or under it get Quality's six
  // exact angles, so which cells count as slivers does not change.
  bool isSliver(CH c) const {
    if (dt_.is_infinite(c) || c->info().label <= 0) return false;
    const std::array<Point3, 4> corners{toPoint3(c->vertex(0)->point()), toPoint3(c->vertex(1)->point()),
                                        toPoint3(c->vertex(2)->point()), toPoint3(c->vertex(3)->point())};
    if (largestDihedralCosine(corners) < std::cos(options_.sliver_dihedral_deg * M_PI / 180) - 1e-9) return false;
    return minDihedralDeg(c) < options_.sliver_dihedral_deg;
  }

  // Smallest dihedral angle of the cells that inserting zone.point would make in place of
  // conflict cells inside the materials (a new cell's label is not known before insertion;
  // the cell it replaces stands in for it); -1 when one of them would fail T3's criteria
  // (the repair by T3 would start a cascade of insertions, each with new slivers).
  double newStarMinDihedral(const Zone& zone) const {
    const Point3 apex = toPoint3(zone.point);
    double worst = 180;
    for (CH c : zone.cells) {
      if (c->info().label <= 0) continue;
      const MaterialCriteria& crit = options_.criteria.of(c->info().label);
      for (int i = 0; i < 4; ++i) {
        if (std::find(zone.cells.begin(), zone.cells.end(), c->neighbor(i)) != zone.cells.end()) continue;
        const VH a = c->vertex((i + 1) & 3), b = c->vertex((i + 2) & 3), d = c->vertex((i + 3) & 3);
        if (dt_.is_infinite(a) || dt_.is_infinite(b) || dt_.is_infinite(d)) continue;
        const double r = std::sqrt(CGAL::squared_distance(CGAL::circumcenter(a->point(), b->point(), d->point(), zone.point),
                                                          zone.point));
        double shortest = std::min({CGAL::squared_distance(a->point(), b->point()),
                                    CGAL::squared_distance(b->point(), d->point()),
                                    CGAL::squared_distance(d->point(), a->point())});
        for (VH w : {a, b, d}) shortest = std::min(shortest, CGAL::squared_distance(w->point(), zone.point));
        shortest = std::sqrt(shortest);
        if ((crit.cell_size > 0 && r > crit.cell_size) ||
            (crit.cell_radius_edge_ratio > 0 && r > crit.cell_radius_edge_ratio * shortest))
          return -1;
        worst = std::min(worst, minDihedralDeg(toPoint3(a->point()), toPoint3(b->point()), toPoint3(d->point()), apex));
      }
    }
    return worst;
  }

  // Whether rule S leaves subsegment s unsplit (the terminator's conditions of T3).
  bool sliverRefusesSplit(int s, uint64_t stamp, const char* rule) {
    if (nearSmallAngle(segments_[s])) {
      leave("cell", std::string(rule) + " would split a subsegment next to an input angle under 60 degrees", stamp, -1);
      return true;
    }
    if (length(segments_[s]) / 2 < terminatorLength_) {
      leave("cell", std::string(rule) + " would split a subsegment below the terminator length", stamp, -1);
      return true;
    }
    return false;
  }

  // One try of rule S on sliver c; true when a point went in.
  bool refineSliver(CH c, std::mt19937& random) {
    const uint64_t stamp = c->info().stamp;
    const Point3 centre = c->info().circumcentre;
    const double pick = kSliverPickRadius * c->info().radius;
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    double bestScore = minDihedralDeg(c);
    Zone best;
    bool found = false;
    for (int k = 0; k <= kSliverCandidates; ++k) {
      Point3 offset{0, 0, 0};
      if (k > 0) do offset = {unit(random), unit(random), unit(random)};
        while (dot(offset, offset) > 1);
      Zone zone = examine(centre + pick * offset, c);
      if (zone.duplicate || zone.encroached >= 0 || zone.insertionRadius < terminatorLength_) continue;
      Point3 ballCentre;
      if (surfaceBallContaining(zone, ballCentre)) continue;
      const double score = newStarMinDihedral(zone);
      if (score > bestScore) {
        bestScore = score;
        best = std::move(zone);
        found = true;
      }
    }
    if (found) {
      commit(best, 3, -1);
      ++stats_.insertions["S.4"];
      return true;
    }
    // No free candidate: the circumcentre goes where T3 would send it.
    const Zone zone = examine(centre, c);
    if (zone.duplicate) {
      leave("cell", "sliver: its circumcentre is a vertex already", stamp, -1);
      return false;
    }
    if (zone.encroached >= 0) {
      if (sliverRefusesSplit(zone.encroached, stamp, "S.1")) return false;
      if (splitEncroached(zone.encroached, "S.1")) return true;
      leave("cell", "sliver: the subsegment its circumcentre encroaches cannot be split", stamp, -1);
      return false;
    }
    Point3 ballCentre;
    int ballEntry = -1;
    if (surfaceBallContaining(zone, ballCentre, &ballEntry)) {
      const Zone surface = examine(ballCentre, c);
      if (!surface.duplicate && surface.encroached >= 0) {
        if (sliverRefusesSplit(surface.encroached, stamp, "S.2")) return false;
        if (splitEncroached(surface.encroached, "S.2")) return true;
      } else if (!surface.duplicate && surface.insertionRadius >= terminatorLength_ &&
                 newStarMinDihedral(surface) > minDihedralDeg(c)) {
        // Only a ball centre whose new cells are better and meet T3's criteria: unlike T3.3,
        // S.3 is not needed for the guarantees, and under a strict radius-edge bound (1.1 on
        // implant_in_bone) a surface point that T3 must repair starts a cascade (3x the tets).
        commit(surface, 2, -1, ballEntry);
        ++stats_.insertions["S.3"];
        return true;
      }
      leave("cell", "sliver: the surface ball centre its circumcentre maps to makes no better cells", stamp, -1);
      return false;
    }
    leave("cell", "sliver: no point near its circumcentre makes better cells", stamp, -1);
    return false;
  }

  void refineSlivers() {
    if (options_.sliver_dihedral_deg <= 0) return;
    control_.report("slivers", 0);
    std::mt19937 random(options_.seed);
    for (int round = 0; round < kSliverRounds; ++round) {
      struct Sliver {
        double angle;
        uint64_t stamp;
        CH cell;
      };
      std::vector<Sliver> slivers;
      for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c)
        if (isSliver(c)) slivers.push_back({minDihedralDeg(c), c->info().stamp, c});
      if (slivers.empty()) return;
      // Worst first; stamps break ties so the order does not depend on memory layout.
      std::sort(slivers.begin(), slivers.end(), [](const Sliver& a, const Sliver& b) {
        return a.angle != b.angle ? a.angle < b.angle : a.stamp < b.stamp;
      });
      int64_t inserted = 0, tried = 0;
      for (const Sliver& s : slivers) {
        if ((++tried & 63) == 0) control_.checkpoint();
        if (s.cell->info().stamp != s.stamp) continue;  // gone with an earlier insertion
        inserted += refineSliver(s.cell, random);
      }
      refine();  // T1-T3 repair what the insertions broke
      if (inserted == 0) return;
    }
  }

  // ------------------------------------------- P: vertex perturbation (beyond the thesis)
  // Rule S leaves slivers whose circumcentre maps to a surface ball centre that makes no
  // better cells (implant_in_bone (a): about 400 of them). Moving one of a sliver's corners
  // instead, as CGAL's perturb_mesh_3 does, lifts most of them without new points; doing it
  // here, on the engine's own triangulation, spares the pipeline rebuilding a Mesh_3 complex
  // for CGAL's perturber (on implant_in_bone (a) that rebuild and perturbation took a third
  // of the job). A move keeps the mesh's guarantees or is undone: only interior and surface
  // corners move (never segment vertices, bounding corners or vertices the planar-face layer
  // tracks), a surface corner goes back onto the boundary through the oracle's projection,
  // and a move stays only when the smallest dihedral angle of the cells it replaces rises,
  // every subsegment there stays an unencroached edge, and every new facet between two
  // labels is a restricted facet on boundary vertices that meets the facet criteria. CGAL's
  // perturbation still runs on whatever is left (Pipeline). Candidate targets are screened
  // cheaply first: the corner's cells with the corner moved, before any Delaunay update.
  static constexpr int kPerturbRounds = 24;
  static constexpr int kPerturbPlainRounds = 6;  // then the slivers left get more effort
  static constexpr int kPerturbMaxEffort = 16;    // x kPerturbCandidates targets per corner
  static constexpr int kPerturbMaxTries = 12;     // moves tried per sliver and round at most
  static constexpr int kPerturbIdleWidest = 3;    // rounds at kPerturbMaxEffort that move nothing
  static constexpr double kIntoCircumsphere = 0.9; // x radius: where a neighbour's vertex goes
  static constexpr int kPerturbCandidates = 10;  // targets screened per corner
  static constexpr int kPerturbMoves = 3;        // moves tried per sliver and round (x effort)
  static constexpr double kPerturbMaxStep = 0.4; // x the sliver's shortest edge

  struct VertexMove {
    VH vertex;
    Point3 target{};
    double before = 0;  // smallest angle of the corner's labelled cells where it is
    double score = 0;   // the same with the corner at target (cells kept as they are)
  };

  struct TrackedCell {
    double angle;
    uint64_t stamp;  // the cell is gone when its stamp changed
    CH cell;
  };

  bool movable(VH v) const {
    if (dt_.is_infinite(v) || v->info().far || v->info().dimension <= 1) return false;
    return planarFacesOfVertex_.empty() || planarFacesOfVertex_[v->info().id].empty();
  }

  // The smallest dihedral angle of a tetrahedron in degrees, from the largest cosine between
  // face normals: one acos instead of the six atan2 of Quality's dihedralAngles, since rule P
  // measures tens of thousands of candidate cells and only compares the results.
  static double smallestDihedralDeg(const std::array<Point3, 4>& p) {
    return std::acos(std::clamp(largestDihedralCosine(p), -1.0, 1.0)) * 180 / M_PI;
  }

  // The cosine of a tetrahedron's smallest dihedral angle (1 for a flat one), without trig.
  static double largestDihedralCosine(const std::array<Point3, 4>& p) {
    static constexpr int kFaceOpposite[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    std::array<Point3, 4> normal;
    std::array<double, 4> length;
    for (int k = 0; k < 4; ++k) {
      const auto& f = kFaceOpposite[k];
      normal[k] = cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]);
      length[k] = norm(normal[k]);
      if (!(length[k] > 0)) return 1;
    }
    double largestCosine = -1;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        largestCosine = std::max(largestCosine, -dot(normal[i], normal[j]) / (length[i] * length[j]));
    return largestCosine;
  }

  // The smallest dihedral angle of cell c with corner `moved` at p (none: VH()), its corners
  // taken by vertex id: the order CGAL stores them in depends on memory layout once vertices
  // have moved, and the rounding must not.
  double minDihedralById(CH c, VH moved, const CgalPoint& p) const {
    std::array<std::pair<int64_t, Point3>, 4> corners;
    for (int k = 0; k < 4; ++k)
      corners[k] = {c->vertex(k)->info().id, toPoint3(c->vertex(k) == moved ? p : c->vertex(k)->point())};
    std::sort(corners.begin(), corners.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    return smallestDihedralDeg({corners[0].second, corners[1].second, corners[2].second, corners[3].second});
  }

  // Smallest dihedral angle of the labelled cells of `star` (the cells of v) with v at p,
  // the cells kept as they are; -1 when one would turn flat or inside out. Stops at the first
  // cell no better than `floor` (the result is then no better than floor either).
  double starMinWithVertexAt(VH v, const std::vector<CH>& star, const CgalPoint& p, double floor) const {
    double worst = 180;
    for (CH c : star) {
      if (dt_.is_infinite(c)) continue;
      std::array<CgalPoint, 4> q;
      for (int k = 0; k < 4; ++k) q[k] = c->vertex(k) == v ? p : c->vertex(k)->point();
      if (CGAL::orientation(q[0], q[1], q[2], q[3]) != CGAL::POSITIVE) return -1;
      if (c->info().label <= 0) continue;
      worst = std::min(worst, minDihedralById(c, v, p));
      if (worst <= floor) return worst;
    }
    return worst;
  }

  // Screened moves of sliver c's movable corners, best first: away from the opposite face
  // (the sliver's volume grows) with a seeded random tilt, steps up to kPerturbMaxStep x its
  // shortest edge. A candidate is kept only when it beats every earlier one of the sliver
  // (branch and bound: the first cell no better ends its screening). Moves after which the
  // corner's cells stay Delaunay come first: the screen then predicts the move's outcome,
  // while a move that flips cells often ends worse than it screened (implant_in_bone (a):
  // the last slivers' largest steps screened at 20-25 degrees and made cells of 7-10).
  std::vector<VertexMove> screenedMoves(CH c, std::mt19937& random, int effort) const {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const double scale = shortestEdge(c);
    std::vector<VertexMove> moves;
    // Corners by vertex id, so the seeded draws go to the same corners in every run.
    std::array<int, 4> corners{0, 1, 2, 3};
    std::sort(corners.begin(), corners.end(),
              [&](int x, int y) { return c->vertex(x)->info().id < c->vertex(y)->info().id; });
    // Two lists: moves whose star stays Delaunay (the move then makes exactly the screened
    // cells) and the others (the triangulation flips, so the move may end worse).
    std::vector<VertexMove> kept, flipping;
    double best = -1, bestFlipping = -1;
    for (int k : corners) {
      const VH v = c->vertex(k);
      if (!movable(v)) continue;
      std::vector<CH> star;
      dt_.incident_cells(v, std::back_inserter(star));
      const double before = starMinWithVertexAt(v, star, v->point(), -1);
      std::array<Point3, 3> face;  // the opposite face, by vertex id
      for (int n = 0, m = 0; n < 4; ++n)
        if (corners[n] != k) face[m++] = toPoint3(c->vertex(corners[n])->point());
      const Point3 p = toPoint3(v->point()), a = face[0], b = face[1], d = face[2];
      Point3 away = cross(b - a, d - a);
      const double len = norm(away);
      if (!(len > 0)) continue;
      away = (dot(away, p - a) < 0 ? -1.0 : 1.0) / len * away;
      // A surface corner moves in its tangent plane (the oracle's projection would undo the
      // rest): there a flat sliver's opposite face is about parallel to the surface, so the
      // seeded tilt leads and the move is screened where the projection will put it.
      const Point3 normal = v->info().dimension == 2 ? surfaceNormalAt(v, star) : Point3{0, 0, 0};
      const bool onSurface = dot(normal, normal) > 0;
      const int candidates = kPerturbCandidates * effort;
      for (int j = 0; j < candidates; ++j) {
        Point3 tilt;
        do tilt = {unit(random), unit(random), unit(random)};
        while (dot(tilt, tilt) > 1);
        const double step = kPerturbMaxStep * scale * (j + 1) / candidates;
        if (step < terminatorLength_) continue;  // refused by the move (cellsChangedByMove)
        Point3 direction = onSurface ? 0.3 * away + tilt : away + 0.7 * tilt;
        if (onSurface) direction = direction - dot(direction, normal) * normal;
        if (!(norm(direction) > 0)) continue;
        const Point3 target = p + (step / norm(direction)) * direction;
        const double floor = std::max(before, best);
        const double score = starMinWithVertexAt(v, star, toCgal(target), floor);
        if (score <= floor) continue;
        if (starStaysDelaunay(v, star, toCgal(target))) {
          best = score;
          kept.push_back({v, target, before, score});
        } else if (score > bestFlipping) {
          bestFlipping = score;
          flipping.push_back({v, target, before, score});
        }
      }
    }
    // Scores rose along each list: the best kept move first, flipping ones last.
    moves.assign(kept.rbegin(), kept.rend());
    if (effort >= kPerturbMaxEffort) intoCircumsphereMoves(c, scale, moves);
    moves.insert(moves.end(), flipping.rbegin(), flipping.rend());
    return moves;
  }

  // Last resort for a sliver its own corners cannot lift: the movable vertex of a neighbour
  // (across one of its facets) moved just inside the sliver's circumsphere, which deletes
  // the sliver. Slivers' neighbours are about cospherical with them, so the step is short;
  // the move's cells are unknown before it is made (score 0: tryVertexMove judges it).
  void intoCircumsphereMoves(CH c, double scale, std::vector<VertexMove>& moves) const {
    std::array<VH, 4> corners{c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
    std::sort(corners.begin(), corners.end(), [](VH x, VH y) { return x->info().id < y->info().id; });
    const Point3 centre = toPoint3(CGAL::circumcenter(corners[0]->point(), corners[1]->point(), corners[2]->point(),
                                                      corners[3]->point()));
    const double radius = distance(centre, toPoint3(corners[0]->point()));
    std::vector<VH> across;
    for (int i = 0; i < 4; ++i) {
      const CH n = c->neighbor(i);
      const VH w = n->vertex(n->index(c));
      if (movable(w)) across.push_back(w);
    }
    std::sort(across.begin(), across.end(), [](VH x, VH y) { return x->info().id < y->info().id; });
    for (VH w : across) {
      const Point3 p = toPoint3(w->point());
      const double out = distance(p, centre);
      const double step = out - kIntoCircumsphere * radius;
      if (!(out > 0) || step > kPerturbMaxStep * scale || step < terminatorLength_) continue;
      std::vector<CH> star;
      dt_.incident_cells(w, std::back_inserter(star));
      moves.push_back({w, p + (step / out) * (centre - p), starMinWithVertexAt(w, star, w->point(), -1), 0});
    }
  }

  // Whether the cells of v (`star`) stay a Delaunay triangulation with v moved to p: no
  // vertex across one of their facets lies inside or on the circumsphere of the moved cell.
  // Then moving v makes exactly these cells and the screened score is the move's outcome.
  bool starStaysDelaunay(VH v, const std::vector<CH>& star, const CgalPoint& p) const {
    for (CH c : star) {
      if (dt_.is_infinite(c)) return false;
      std::array<CgalPoint, 4> q;
      for (int k = 0; k < 4; ++k) q[k] = c->vertex(k) == v ? p : c->vertex(k)->point();
      for (int i = 0; i < 4; ++i) {
        const CH n = c->neighbor(i);
        const VH across = n->vertex(n->index(c));
        if (dt_.is_infinite(across)) continue;
        if (CGAL::side_of_oriented_sphere(q[0], q[1], q[2], q[3], across->point()) != CGAL::ON_NEGATIVE_SIDE)
          return false;
      }
    }
    return true;
  }

  // Unit normal of the boundary at surface vertex v: the mean of the normals of the restricted
  // facets at v (their sides made to agree with the first); zero when v has none. Facets and
  // their corners go by vertex id: the star's order and the cells' corner order depend on
  // memory layout once vertices have moved, and the rounding must not.
  Point3 surfaceNormalAt(VH v, const std::vector<CH>& star) const {
    std::vector<std::array<VH, 3>> facets;
    for (CH c : star) {
      const int at = c->index(v);
      for (int i = 0; i < 4; ++i) {
        if (i == at || !c->info().facets[i].restricted) continue;
        std::array<VH, 3> f{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
        std::sort(f.begin(), f.end(), [](VH x, VH y) { return x->info().id < y->info().id; });
        facets.push_back(f);
      }
    }
    const auto ids = [](const std::array<VH, 3>& f) {
      return std::array<int64_t, 3>{f[0]->info().id, f[1]->info().id, f[2]->info().id};
    };
    std::sort(facets.begin(), facets.end(), [&](const auto& x, const auto& y) { return ids(x) < ids(y); });
    facets.erase(std::unique(facets.begin(), facets.end()), facets.end());  // seen from both sides
    Point3 sum{0, 0, 0};
    for (const auto& f : facets) {
      const Point3 a = toPoint3(f[0]->point()), b = toPoint3(f[1]->point()), d = toPoint3(f[2]->point());
      Point3 n = cross(b - a, d - a);
      const double len = norm(n);
      if (!(len > 0)) continue;
      n = (dot(n, sum) < 0 ? -1.0 : 1.0) / len * n;
      sum = sum + n;
    }
    const double len = norm(sum);
    return len > 0 ? (1.0 / len) * sum : Point3{0, 0, 0};
  }

  // The cells moving v to target deletes (v's cells and the target's conflict zone) and the
  // alive subsegments among their edges; false when target is a vertex already or closer
  // than the terminator length to one.
  bool cellsChangedByMove(VH v, const Point3& target, std::vector<CH>& cells, std::vector<int>& segments) const {
    Zone zone = examine(target, v->cell());
    if (zone.duplicate || zone.insertionRadius < terminatorLength_) return false;
    cells = std::move(zone.cells);
    std::vector<CH> star;
    dt_.incident_cells(v, std::back_inserter(star));
    for (CH c : star)
      if (std::find(cells.begin(), cells.end(), c) == cells.end()) cells.push_back(c);
    segments.clear();
    for (CH c : cells)
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
          const VH va = c->vertex(a), vb = c->vertex(b);
          if (dt_.is_infinite(va) || dt_.is_infinite(vb)) continue;
          auto it = segmentOf_.find(pairKey(va->info().id, vb->info().id));
          if (it != segmentOf_.end() && std::find(segments.begin(), segments.end(), it->second) == segments.end())
            segments.push_back(it->second);
        }
    return true;
  }

  std::array<int64_t, 4> cornerIds(CH c) const {
    std::array<int64_t, 4> ids;
    for (int k = 0; k < 4; ++k) ids[k] = dt_.is_infinite(c->vertex(k)) ? -1 : c->vertex(k)->info().id;
    std::sort(ids.begin(), ids.end());
    return ids;
  }

  // Moves v to target in the triangulation and evaluates the new cells and their facets, in
  // an order that does not depend on memory layout (stamps break ties elsewhere). A cell
  // found in `before` (by its corners: an undo restores the cells the move deleted) takes
  // its saved evaluation back, with its facets on both sides, instead of asking the oracle.
  // A cell's evaluation kept for an undo, with its corners in its own order: facet i is
  // opposite corner i, and the restored cell may list its corners in another order.
  struct SavedCell {
    CellInfo info;
    std::array<VH, 4> corners;
  };

  std::vector<CH> relocate(VH v, const Point3& target, const std::vector<CH>& changed,
                           const std::map<std::array<int64_t, 4>, SavedCell>* before = nullptr) {
    for (CH c : changed) c->info().stamp = 0;  // queued entries of deleted cells read as stale
    std::vector<CH> fresh;
    dt_.move_if_no_collision_and_give_new_cells(v, toCgal(target), std::back_inserter(fresh));
    std::vector<std::pair<std::array<int64_t, 4>, CH>> ordered;
    for (CH c : fresh) ordered.emplace_back(cornerIds(c), c);
    std::sort(ordered.begin(), ordered.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    fresh.clear();
    for (const auto& [ids, c] : ordered) {
      fresh.push_back(c);
      auto saved = before ? before->find(ids) : before->end();
      if (!before || saved == before->end()) {
        evaluateCell(c);
        continue;
      }
      c->info() = saved->second.info;
      c->info().stamp = ++stampCounter_;
      for (int i = 0; i < 4; ++i) {
        const auto& was = saved->second.corners;
        c->info().facets[i] = saved->second.info.facets[std::find(was.begin(), was.end(), c->vertex(i)) - was.begin()];
        c->neighbor(i)->info().facets[c->neighbor(i)->index(c)] = c->info().facets[i];
      }
    }
    for (CH c : fresh)
      for (int i = 0; i < 4; ++i)
        if (!c->info().facets[i].known) evaluateFacet(c, i);
    return fresh;
  }

  double smallestLabelledAngle(const std::vector<CH>& cells) const {
    double worst = 180;
    for (CH c : cells)
      if (!dt_.is_infinite(c) && c->info().label > 0) worst = std::min(worst, minDihedralById(c, VH(), CgalPoint()));
    return worst;
  }

  // The guarantees a move must keep (see above), checked on the cells it made.
  bool moveKeepsGuarantees(VH v, const std::vector<CH>& fresh, const std::vector<int>& segments) const {
    for (int s : segments) {
      const Subsegment& seg = segments_[s];
      if (!seg.alive) continue;
      CH c;
      int i, j;
      if (!dt_.is_edge(seg.a, seg.b, c, i, j) || strictlyInDiametralBall(v->point(), seg)) return false;
    }
    for (CH c : fresh)
      for (int i = 0; i < 4; ++i) {
        const CH n = c->neighbor(i);
        const int labelHere = dt_.is_infinite(c) ? 0 : c->info().label;
        const int labelThere = dt_.is_infinite(n) ? 0 : n->info().label;
        if (c->info().facets[i].restricted ? facetBadness(c, i) > 0 : labelHere != labelThere) return false;
      }
    return true;
  }

  // Moves v to target if that keeps the guarantees and raises the smallest dihedral angle of
  // the labelled cells it changes; else puts v back (the Delaunay triangulation of the same
  // points is the same). True when the move stays; the cells made, by the move or its undo,
  // are added to `made`.
  bool tryVertexMove(VH v, const Point3& target, std::vector<CH>& made) {
    const Point3 origin = toPoint3(v->point());
    std::vector<CH> changed;
    std::vector<int> segments;
    if (!cellsChangedByMove(v, target, changed, segments)) return false;
    const double before = smallestLabelledAngle(changed);
    std::map<std::array<int64_t, 4>, SavedCell> saved;
    for (CH c : changed)
      saved.emplace(cornerIds(c), SavedCell{c->info(), {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)}});
    const std::vector<CH> fresh = relocate(v, target, changed);
    if (smallestLabelledAngle(fresh) > before && moveKeepsGuarantees(v, fresh, segments)) {
      made.insert(made.end(), fresh.begin(), fresh.end());
      return true;
    }
    std::vector<int> unused;
    if (!cellsChangedByMove(v, origin, changed, unused))
      throw Error("internal error: the thesis engine could not undo a vertex move");
    const std::vector<CH> restored = relocate(v, origin, changed, &saved);
    made.insert(made.end(), restored.begin(), restored.end());
    return false;
  }

  // One try of rule P on sliver c (up to kPerturbMoves x effort moves, so the few slivers of
  // the late rounds also reach the screen's lesser candidates, which a corner's guarantees
  // may need); true when a corner moved. c may be gone afterwards either way: the cells made
  // in its place are added to `made`.
  bool perturbSliver(CH c, std::mt19937& random, int effort, std::vector<CH>& made) {
    int tries = 0;
    for (const VertexMove& m : screenedMoves(c, random, effort)) {
      if (tries == std::min(kPerturbMoves * effort, kPerturbMaxTries)) break;
      Point3 target = m.target;
      int targetEntry = -1;
      if (m.vertex->info().dimension == 2) {
        const BoundaryProjection onBoundary = oracle_.projectOnBoundary(target, &targetEntry);
        if (!std::isfinite(onBoundary.distance)) continue;
        target = onBoundary.point;
        std::vector<CH> star;
        dt_.incident_cells(m.vertex, std::back_inserter(star));
        if (m.score > 0 && starMinWithVertexAt(m.vertex, star, toCgal(target), m.before) <= m.before) continue;
      }
      // A step under the terminator length is refused by the move (see cellsChangedByMove):
      // no try is spent on it.
      if (distance(target, toPoint3(m.vertex->point())) < terminatorLength_) continue;
      ++tries;
      if (tryVertexMove(m.vertex, target, made)) {
        // An undone move leaves v where it was, with the entry it had.
        m.vertex->info().boundaryEntry = targetEntry;
        ++stats_.insertions["P"];
        return true;
      }
    }
    return false;
  }

  void trackIfSliver(CH c, std::vector<TrackedCell>& slivers) const {
    if (dt_.is_infinite(c) || c->info().label <= 0) return;
    const double angle = minDihedralById(c, VH(), CgalPoint());
    if (angle < options_.sliver_dihedral_deg) slivers.push_back({angle, c->info().stamp, c});
  }

  void perturbSlivers() {
    if (options_.sliver_dihedral_deg <= 0) return;
    control_.report("vertex moves", 0);
    movingVertices_ = true;
    std::mt19937 random(options_.seed + 1);
    // The first round looks at every cell; later ones at the slivers still there and the
    // cells the moves made.
    std::vector<TrackedCell> slivers;
    for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) trackIfSliver(c, slivers);
    int effort = 1, idleWidest = 0;
    for (int round = 0; round < kPerturbRounds && !slivers.empty(); ++round) {
      std::sort(slivers.begin(), slivers.end(), [](const TrackedCell& x, const TrackedCell& y) {
        return x.angle != y.angle ? x.angle < y.angle : x.stamp < y.stamp;
      });
      // A cell can be listed twice: a later try may make it in the memory of a cell an
      // earlier try made and deleted, which depends on memory layout. Each visit draws from
      // `random`, so a second one would make the mesh depend on that layout.
      slivers.erase(std::unique(slivers.begin(), slivers.end(),
                                [](const TrackedCell& x, const TrackedCell& y) { return x.stamp == y.stamp; }),
                    slivers.end());
      // The few slivers the first rounds leave get more candidates each, and more again
      // after a round that moved nothing (the last ones need the rare targets that keep
      // their corner's cells Delaunay and their guarantees).
      if (round == kPerturbPlainRounds) effort = std::max(effort, 4);
      std::vector<std::pair<uint64_t, CH>> made;  // stamp, cell
      std::vector<TrackedCell> next;
      int64_t moved = 0, tried = 0;
      for (const TrackedCell& s : slivers) {
        if ((++tried & 63) == 0) control_.checkpoint();
        if (s.cell->info().stamp != s.stamp) continue;  // changed by an earlier move
        std::vector<CH> cells;
        moved += perturbSliver(s.cell, random, effort, cells);
        // Cells made by an undone try may be gone with the next try (stamp 0).
        for (CH c : cells)
          if (c->info().stamp != 0) made.emplace_back(c->info().stamp, c);
        if (s.cell->info().stamp == s.stamp) next.push_back(s);
      }
      if (moved == 0) {
        if (effort >= kPerturbMaxEffort && ++idleWidest == kPerturbIdleWidest) return;
        effort = std::min(4 * effort, kPerturbMaxEffort);
      }
      for (const auto& [stamp, c] : made)
        if (c->info().stamp == stamp) trackIfSliver(c, next);
      // A sliver kept in `next` may have been changed by a later move of the round.
      next.erase(std::remove_if(next.begin(), next.end(),
                                [](const TrackedCell& s) { return s.cell->info().stamp != s.stamp; }),
                 next.end());
      slivers.swap(next);
    }
  }

  // Cells inside the materials still under the sliver bound, with the reason rule S left
  // them (perturbation, which runs next, works on them).
  void listLeftSlivers() {
    if (options_.sliver_dihedral_deg <= 0) return;
    constexpr size_t kListed = 200;  // the worst ones; the count is complete
    std::vector<std::pair<double, LeftElement>> left;
    for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
      if (!isSliver(c)) continue;
      const double angle = minDihedralDeg(c);
      auto it = leftReasons_.find({c->info().stamp, -1});
      const std::string why = it != leftReasons_.end() ? it->second : "made by the last round's T1-T3 repairs";
      std::ostringstream reason;
      reason << "smallest dihedral angle under " << options_.sliver_dihedral_deg << " degrees (" << why << ")";
      left.push_back({angle, {"cell", reason.str(), c->info().circumcentre, c->info().label, angle}});
    }
    std::stable_sort(left.begin(), left.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    stats_.insertions["left_slivers"] = static_cast<int64_t>(left.size());
    stats_.slivers_left.clear();
    for (size_t k = 0; k < left.size() && k < kListed; ++k) stats_.slivers_left.push_back(std::move(left[k].second));
  }

  // ---------------------------------------------------------------------------- output
  // The corners of the cells inside the materials, in the order the mesh lists them: the
  // triangulation's own order unless vertices have moved (rule P). CGAL's vertex removal,
  // which a move uses, creates cells in an order of handle addresses, which differ between
  // runs; the mesh (and the optimizers and snap that follow, which depend on its order) must
  // not. Then cells are sorted by their corners' vertex ids, each cell starting at its
  // smallest id with its orientation kept.
  struct LabelledCell {
    std::array<VH, 4> corners;
    int label;
  };

  std::vector<LabelledCell> labelledCellsInOutputOrder() const {
    std::vector<LabelledCell> cells;
    for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c)
      if (c->info().label > 0) cells.push_back({{c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)}, c->info().label});
    if (stats_.insertions.count("P") == 0) return cells;
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

  TetMesh extract() const {
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

  void finalCheck() {
    stats_.constrained_subsegments = stats_.subsegments_not_edges = stats_.encroached_subsegments = 0;
    for (const Subsegment& s : segments_) {
      if (!s.alive) continue;
      ++stats_.constrained_subsegments;
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

  void listLeftElements() {
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
    stats_.insertions["left_elements"] = static_cast<int64_t>(left.size());
    if (stats_.left.size() > kListed) stats_.left.resize(kListed);
  }

  const HierarchicalOracle& oracle_;
  const FeatureGraph& features_;
  const RuleSetTOptions& options_;
  const RunControl& control_;
  RuleSetTStatistics& stats_;

  Delaunay dt_;
  CH lastCell_;
  int64_t nextVertexId_ = 0;
  uint64_t stampCounter_ = 0;
  double reach_ = 0;
  double terminatorLength_ = 0;

  std::vector<Subsegment> segments_;
  std::vector<Subsegment> pendingSegments_;
  std::unordered_map<uint64_t, int> segmentOf_;
  std::vector<std::vector<int>> segmentsAt_;  // by vertex id
  std::vector<Star> stars_;
  std::unordered_map<int64_t, int> starOfVertex_;
  std::vector<Point3> smallAnglePoints_;
  std::vector<int> unsplittable_;  // split point is a vertex already (left as they are)

  std::priority_queue<QueueEntry> segmentQueue_, facetQueue_, cellQueue_;
  std::map<std::pair<uint64_t, int>, std::string> leftReasons_;

  // Planar-face layer: the vertices on each face's plane (by face, in insertion order), the
  // faces each vertex lies on (by vertex id), the triangles found missing, and why the ones
  // given up on were left.
  std::vector<std::vector<VH>> planarVertices_;
  std::vector<std::vector<int>> planarFacesOfVertex_;
  std::vector<QueuedPlanarTriangle> planarQueue_;
  std::map<std::array<int64_t, 3>, std::string> planarLeft_;
  int64_t verticesAtPlanarCheck_ = -1;
  bool planarChecked_ = false;
  bool movingVertices_ = false;  // rule P has started (see cornersForRounding)
};

void validate(const HierarchicalOracle& oracle, const RuleSetTOptions& options) {
  auto check = [](const MaterialCriteria& c, const std::string& what) {
    if (!(c.cell_size > 0) || !(c.facet_size > 0) || !(c.facet_distance > 0))
      throw InputError("criteria " + what + ": the thesis engine needs positive cell_size, facet_size and facet_distance");
    if (c.cell_radius_edge_ratio != 0 && c.cell_radius_edge_ratio < 1)
      throw InputError("criteria " + what + ": cell_radius_edge_ratio must be at least 1 (or 0 = off); the thesis "
                       "uses 1.1 to 2");
  };
  check(options.criteria.defaults, "default");
  for (const auto& [m, c] : options.criteria.per_material) check(c, "of material " + std::to_string(m));
  if (!(oracle.diagonal() > 0)) throw InputError("the inputs have no extent: nothing to mesh");
}

}  // namespace

TetMesh meshWithRuleSetT(const HierarchicalOracle& oracle, const FeatureGraph& features,
                         const RuleSetTOptions& options, const RunControl& control, RuleSetTStatistics* statistics) {
  validate(oracle, options);
  RuleSetTStatistics local;
  RuleSetTStatistics& stats = statistics ? *statistics : local;
  RuleSetTRefiner refiner(oracle, features, options, control, stats);
  TetMesh mesh = refiner.run();
  if (mesh.tets.empty())
    throw InputError("the thesis engine produced no tetrahedra: the inputs may be smaller than the sizes asked for; "
                     "lower cell_size and facet_size below the smallest part's thickness");
  return mesh;
}

}  // namespace oraclemesh
