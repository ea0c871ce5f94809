#pragma once
// The refiner behind meshWithRuleSetT (internal to refine/): the CGAL Delaunay triangulation
// it refines, what it keeps on vertices, cells, facets and subsegments, its queues, and the
// class whose levels are defined one file each, in the thesis' order (Rule Set T, thesis
// §3.3.1):
//   ConstrainedSegments.cpp  T1   bad constrained subsegments (star-vertex rules, encroachment,
//                                 subsegments no labelled cell has)
//   PlanarFaceLayer.cpp      TP   planar faces (thesis §4.1), a layer behind RefinementHook
//   RestrictedFacets.cpp     T2   restricted facets and their surface Delaunay balls
//   Cells.cpp                T3   cells inside the materials
//   SliverRule.cpp           the sliver rule (beyond the thesis)
//   VertexMoves.cpp          rule P, vertex moves (beyond the thesis)
//   Insertion.cpp            the insertion core every level inserts through
//   InitialPoints.cpp        the initial point set
//   Output.cpp               the mesh and the report of what was left
//   ThesisEngine.cpp         the driver (phases, the refinement loop) and meshWithRuleSetT
// Only these files include this header: it instantiates the triangulation templates.
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <queue>
#include <random>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "features/RuleSetQ.h"
#include "refine/ThesisEngine.h"

namespace oraclemesh::refine {

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
  // Both sizing fields at the vertex, read once per position (rule P moves vertices): the
  // Lipschitz lower bounds of the cell and facet criteria start from them (fieldsBelow).
  Point3 fieldsReadAt{std::numeric_limits<double>::quiet_NaN(), 0, 0};
  CriteriaTable::FieldValues fields;
  // The B-rep face of boundaryEntry that a dimension-2 vertex lies on, read once per position
  // (patchOf): -1 when unknown or not a B-rep.
  Point3 patchReadAt{std::numeric_limits<double>::quiet_NaN(), 0, 0};
  int patch = -1;
};

// What the dual Voronoi edge of a facet says about the boundary. Kept on both cells of the
// facet and recomputed whenever one of them is new.
struct FacetData {
  bool known = false;
  bool restricted = false;
  Point3 centre{};  // surface Delaunay ball centre: where the dual edge crosses the boundary
  int labelA = 0, labelB = 0;
  int entry = -1;   // the oracle entry whose boundary that crossing is on
  // Between two materials: the width of the widest gap or wedge of empty space that the dual
  // edge crosses (0: none, or none wider than the contact tolerance), and whether a corner
  // lies farther than the contact tolerance from one of the two parts (FacetCriteria.h).
  double bridge = 0;
  bool offInterface = false;
  bool acrossSharpEdge = false;  // two corners on faces meeting at under 60 degrees (FacetCriteria.h)
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

inline Point3 toPoint3(const CgalPoint& p) { return {p.x(), p.y(), p.z()}; }
inline CgalPoint toCgal(const Point3& p) { return CgalPoint(p[0], p[1], p[2]); }

// A cell's corners in the order the triangulation stores them.
inline std::array<Point3, 4> cornerPoints(CH c) {
  return {toPoint3(c->vertex(0)->point()), toPoint3(c->vertex(1)->point()), toPoint3(c->vertex(2)->point()),
          toPoint3(c->vertex(3)->point())};
}

inline uint64_t pairKey(int64_t a, int64_t b) {
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

// A layer between the core's levels, as the planar-face layer (TP) sits between T1 and T2.
// The core calls it at these fixed points only; everything else the layer does, it does
// through the refiner's public members (examine, commit, splitEncroached, ...).
class RefinementHook {
 public:
  virtual ~RefinementHook() = default;
  // A vertex was added and has its id, dimension, curve and far flag.
  virtual void vertexAdded(VH v) = 0;
  // Whether cell c takes its material from its barycentre whatever the job's assignment.
  virtual bool labelsByBarycentre(CH c) const = 0;
  // Whether c's circumsphere is undefined for the layer (four corners on one of its planes):
  // then a cell labelled by its barycentre uses the circle centre of its largest facet.
  virtual bool hasUndefinedCircumsphere(CH c) const = 0;
  // One step of the layer, tried after T1 and before T2; true when a point went in.
  virtual bool refineOne() = 0;
  // The queues are empty and no subsegment is bad: true when the layer found work again.
  virtual bool queuesEmptied() = 0;
  // Refinement has converged (before the elements left are listed); the layer's final
  // check runs in the phase named by checkPhase() (statistics.seconds).
  virtual void refinementDone() = 0;
  virtual const char* checkPhase() const = 0;
  // Whether rule P must leave vertex v where it is.
  virtual bool pinsVertex(VH v) const = 0;
};

class RuleSetTRefiner {
 public:
  RuleSetTRefiner(const HierarchicalOracle& oracle, const FeatureGraph& features, const RuleSetTOptions& options,
                  const RunControl& control, RuleSetTStatistics& stats);

  // Before run(): the layer the core calls at its fixed points (null = none).
  void setHook(RefinementHook* hook) { hook_ = hook; }
  TetMesh run();

  // ------------------------------------------- what the levels and the hook build on
  const HierarchicalOracle& oracle() const { return oracle_; }
  const RuleSetTOptions& options() const { return options_; }
  RuleSetTStatistics& statistics() { return stats_; }
  const Delaunay& triangulation() const { return dt_; }
  const std::vector<Subsegment>& segments() const { return segments_; }
  // Terminator: no point goes in closer than the terminator length at it to a vertex, and no
  // subsegment is split below twice the length at its midpoint. The length at p is 1/32 of the
  // smallest size the caps and the sizing field's gaps ask for there: small only between
  // parts close together, which it keeps apart (one length for the whole mesh from the field's
  // smallest size let Rule Set T cascade next to every small input angle).
  double terminatorAt(const Point3& p) const;
  // Lower bounds of both sizing fields at p from the values kept on the given vertices: each
  // field is Lipschitz with its grading, so at distance d from a vertex it is at least the
  // vertex's value minus grading * d. A criterion met with these sizes is met with the exact
  // ones (larger sizes only admit more), which then need no query at p. Infinity for a field
  // that is not set; 0 where no vertex gives a positive bound.
  CriteriaTable::FieldValues fieldsBelow(const Point3& p, const VH* vertices, int count) const;
  bool belowTerminator(const Zone& zone) const;     // zone.point closer than it to a vertex
  bool belowTerminator(const Subsegment& s) const;  // half of s shorter than it at s's midpoint
  double length(const Subsegment& s) const;

  // Insertion core (Insertion.cpp). examine looks at p's conflict zone (`splitting`: the
  // subsegment p splits, which does not count as encroached); commit inserts its point.
  Zone examine(const Point3& p, CH hint, int splitting = -1) const;
  // boundaryEntry: the oracle entry on whose boundary zone.point lies exactly, if known.
  VH commit(const Zone& zone, int dimension, int curve, int boundaryEntry = -1);
  // Whether a point may go in as it is: no vertex there, no subsegment encroached, and no
  // vertex closer than the terminator length.
  bool isFree(const Zone& zone) const;
  // Inserts p if its zone is free; else nothing changes and the result is VH().
  VH insertIfFree(const Point3& p, CH hint, int dimension, int curve, int boundaryEntry = -1);

  // T1 (ConstrainedSegments.cpp).
  bool strictlyInDiametralBall(const CgalPoint& p, const Subsegment& s) const;
  // A redirection of T2.1 / T3.1 / T3.2 (or of a layer) to subsegment `index`: the T1 rule
  // decides where it is split (star rules first, else the midpoint). Counted under `rule`.
  bool splitEncroached(int index, const std::string& rule);
  // Pops the segment queue until one bad subsegment is split; false when none is left.
  bool refineOneSegment();

  // The initial point set (InitialPoints.cpp).
  void insertInitialPoints();

 private:
  // ---------------------------------------------------- insertion core (Insertion.cpp)
  void setInfo(VH v, int dimension, int curve, bool far = false);
  void afterInsertion(VH v);
  void leave(const std::string& kind, const std::string& reason, uint64_t stamp, int facet);
  // A redirection inserts another point than the element's own, which may leave the element
  // in place: it goes back into its queue (and is dropped there once it is gone or good).
  static bool requeue(std::priority_queue<QueueEntry>& queue, const QueueEntry& e) {
    if (e.cell->info().stamp == e.stamp) queue.push(e);
    return true;
  }

  // ------------------------------------------------- T1 (ConstrainedSegments.cpp)
  // Where a bad subsegment is split, and under which rule; rule empty when it is good.
  struct SegmentSplit {
    std::string rule;
    Point3 point{};
  };
  void addSegment(VH a, VH b, int curve);
  void removeSegment(int index);
  bool encroached(const Subsegment& s) const;
  // A Delaunay edge none of whose cells has a material label: the mesh would not have it (T1.3).
  bool outsideEveryMaterial(const Subsegment& s) const;
  // T1.3's last resort once no vertex moves any more (keepSubsegmentsInMaterial).
  void keepSubsegmentsInMaterial();
  int starAt(VH v) const;
  double shortestAtStar(int star) const;
  SegmentSplit badSegmentSplit(int index, bool assumeEncroached) const;
  static double firstSplitRadius(const Star& star);
  Point3 pointOnCurve(int curve, const Point3& p, const Point3* from = nullptr, double radius = 0) const;
  Point3 splitPointOnCurve(const Subsegment& s, const Point3& p, const Point3* from = nullptr,
                           double radius = 0) const;
  void pushSegment(int index);
  bool splitSegment(int index, const Point3& point, const std::string& rule);
  bool nearSmallAngle(const Subsegment& s) const;
  bool encroachmentTerminatorRefuses(int index);
  // At a fixpoint of every queue: queues the subsegments still bad; true when there are some.
  bool queueBadSegments();

  // --------------------------------------------------- T2 (RestrictedFacets.cpp)
  void dualOf(CH c, int i, Point3& from, Point3& to, int& labelFrom, int& labelTo) const;
  bool offInterface(CH c, int i, int materialA, int materialB) const;
  bool nearMaterial(VH v, int material) const;
  int patchOf(VH v) const;
  bool acrossSharpEdge(CH c, int i) const;
  double bridgedGap(const std::vector<CompositeCrossing>& crossings, double narrow) const;
  void evaluateFacet(CH c, int i);
  double facetBadness(CH c, int i, std::string* reason = nullptr, bool withAngle = true) const;
  bool refineOneFacet();
  bool facetAngleTerminatorRefuses(const QueueEntry& e, int s);
  bool surfaceBallContaining(const Zone& zone, Point3& centre, int* entry = nullptr) const;

  // ---------------------------------------------------------------- T3 (Cells.cpp)
  void evaluateCell(CH c);
  std::array<VH, 4> cornersForRounding(CH c) const;
  static Point3 barycentre(CH c);
  void useCircleCentre(CH c, CellInfo& info) const;
  double cellBadness(CH c, bool* sizeFails = nullptr, std::string* reason = nullptr) const;
  static double flatness(CH c);
  static double shortestEdge(CH c);
  static double longestEdge(CH c);
  bool refinedAtCircumcentre(CH c) const;
  Point3 refinementPoint(CH c, bool atCircumcentre) const;
  bool refineOneCell();

  // ----------------------------------------------------- the sliver rule (SliverRule.cpp)
  static double minDihedralDeg(CH c);
  bool isSliver(CH c) const;
  double newStarMinDihedral(const Zone& zone) const;
  bool sliverRefusesSplit(int s, uint64_t stamp, const char* rule);
  bool refineSliver(CH c, std::mt19937& random);
  void refineSlivers();
  void listLeftSlivers();

  // ------------------------------------------------------ rule P (VertexMoves.cpp)
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
  // A cell's evaluation kept for an undo, with its corners in its own order: facet i is
  // opposite corner i, and the restored cell may list its corners in another order.
  struct SavedCell {
    CellInfo info;
    std::array<VH, 4> corners;
  };
  bool movable(VH v) const;
  double minDihedralById(CH c, VH moved, const CgalPoint& p) const;
  double starMinWithVertexAt(VH v, const std::vector<CH>& star, const CgalPoint& p, double floor) const;
  std::vector<VertexMove> screenedMoves(CH c, std::mt19937& random, int effort) const;
  void intoCircumsphereMoves(CH c, double scale, std::vector<VertexMove>& moves) const;
  bool starStaysDelaunay(VH v, const std::vector<CH>& star, const CgalPoint& p) const;
  Point3 surfaceNormalAt(VH v, const std::vector<CH>& star) const;
  bool cellsChangedByMove(VH v, const Point3& target, bool undo, std::vector<CH>& cells,
                          std::vector<int>& segments) const;
  std::array<int64_t, 4> cornerIds(CH c) const;
  std::vector<CH> relocate(VH v, const Point3& target, const std::vector<CH>& changed,
                           const std::map<std::array<int64_t, 4>, SavedCell>* before = nullptr);
  double smallestLabelledAngle(const std::vector<CH>& cells) const;
  bool moveKeepsGuarantees(VH v, const std::vector<CH>& fresh, const std::vector<int>& segments) const;
  bool tryVertexMove(VH v, const Point3& target, std::vector<CH>& made);
  bool perturbSliver(CH c, std::mt19937& random, int effort, std::vector<CH>& made);
  void trackIfSliver(CH c, std::vector<TrackedCell>& slivers) const;
  void perturbSlivers();

  // ------------------------------------------------------------- output (Output.cpp)
  struct LabelledCell {
    std::array<VH, 4> corners;
    int label;
  };
  std::vector<LabelledCell> labelledCellsInOutputOrder() const;
  TetMesh extract() const;
  void finalCheck();
  void listLeftElements();

  // -------------------------------------------------- initial points (InitialPoints.cpp)
  Point3 polylinePointOnCurve(const FeaturePolyline& pl, size_t k) const;
  VH insertOrFind(const Point3& p, int dimension, int curve, bool far = false);
  bool isCurveContinuation(const StarVertex& sv) const;

  // ------------------------------------------------------ driver (ThesisEngine.cpp)
  void refine();

  const HierarchicalOracle& oracle_;
  const FeatureGraph& features_;
  const RuleSetTOptions& options_;
  const RunControl& control_;
  RuleSetTStatistics& stats_;
  RefinementHook* hook_ = nullptr;

  Delaunay dt_;
  CH lastCell_;
  int64_t nextVertexId_ = 0;
  uint64_t stampCounter_ = 0;
  double reach_ = 0;
  double capsTerminator_ = 0;          // 1/32 of the smallest size the caps give
  double terminatorPerGapSize_ = 0;    // the gap sizes at p times this lower it; 0: no gap sizes

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
  // nearMaterial's answers per (vertex id, material), for the facets around a vertex are
  // evaluated again and again; relocate() drops a vertex's when rule P moves it.
  mutable std::map<std::pair<int64_t, int>, bool> nearMaterial_;
  // Materials whose facets the contact-end criteria judge: every entry a B-rep, feature
  // curves in the job, a contact tolerance (constructor).
  std::set<int> contactEndMaterials_;
  bool contactEnds(int materialA, int materialB) const;
  bool movingVertices_ = false;  // rule P has started (see cornersForRounding)
};

}  // namespace oraclemesh::refine
