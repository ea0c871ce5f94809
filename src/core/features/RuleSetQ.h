#pragma once
// Rule Set Q (thesis §3.2.1) and the step before it (thesis §3.2): the segment-splitting rules
// that make Delaunay refinement of constrained segments terminate. First the segments are split
// at their mutual intersections, so that they meet only at their ends. Star vertices are where
// constrained curves meet; the thesis' Q1 makes every segment incident to a star vertex equally
// long (l_min/3) so that splitting one of them never encroaches another.
//
// Our polylines sample smooth curves, so a polyline's inner vertices are not corners: a star
// vertex is an end point shared by two or more polyline ends (a B-rep vertex where edges meet,
// a junction curve leaving a sharp edge, a split at a crossing). A polyline end that no other
// polyline touches is an ordinary end. A closed polyline (a full circle) whose two ends meet at
// its one B-rep vertex makes that vertex a star vertex, as the thesis' definition says.
#include <functional>
#include <optional>
#include <vector>

#include "features/FeatureGraph.h"

namespace oraclemesh {

// Thesis §3.2's step before Rule Set Q ("compute all intersections ... and split the segments
// accordingly"): splits polylines where they cross or touch one another so that every meeting
// point is an end point shared bitwise by all pieces.
// - A pair with a user polyline meets where the two come closer than `tolerance`; the meeting
//   point is taken on the CAD curve (it lies on the CAD edge).
// - Two CAD curves (sharp edges, junction curves) meet where they come closer than
//   `curveTolerance` (their chords stray from the exact curves by the sampling sagitta) at an
//   angle of at least a degree (nearer to parallel they are tangent, not crossing): there both
//   are split at the middle of the closest points. Where one ends on the other (the end within
//   curveTolerance of it, and within 100 x curveTolerance of where they meet: a T), the other
//   is split at that end point; where both ends are that
//   near, they meet at their ends, unless neither end lies on the other curve (within
//   curveTolerance): then they cross near both ends and are split at the crossing. Within
//   `sharedEndClearance` of an end both share, nothing is split: curves leaving a B-rep vertex
//   at a small angle stay close for a while without crossing. Two CAD curves that share a
//   stretch (a segment of one lies on the other: edges of parts in contact along the same
//   arc) are not split against each other. curveTolerance <= 0 leaves CAD pairs alone.
//   Chords of coarsely sampled curves can come that close where the exact curves do not meet
//   (two arcs on parallel planes a fraction of the sampling sagitta apart): when
//   `exactCurveGap` is given, a CAD pair whose exact curves stay more than `tolerance` apart
//   (its value for the pair; negative = unknown) is not split either.
// - Two CAD curves that touch tangentially (a rod's end circle on the edge of the plate it
//   rests on) meet there too. Given `exactCurveProjection` (the nearest point of a polyline's
//   exact curve; nullopt = unknown), chords within reach at under ten degrees are decided on
//   the exact curves, once per neighbourhood of the closest chords: where those chords lie on
//   both curves, the curves share a stretch (not split); else at the end of one lying on the
//   other next to the touching point (a T: the plate's edge clipped where it runs inside the
//   rod), and, when the exact curves touch (exactCurveGap), at the touching point (on the first
//   curve where it comes nearest to the second, and on the second).
// Pieces keep their fields; curves are renumbered 0, 1, ...
using ExactCurveGap = std::function<double(const FeaturePolyline&, const FeaturePolyline&)>;
using ExactCurveProjection = std::function<std::optional<Point3>(const FeaturePolyline&, const Point3&)>;
FeatureGraph splitAtCrossings(const FeatureGraph& graph, double tolerance, double curveTolerance = 0,
                              double sharedEndClearance = 0, const ExactCurveGap& exactCurveGap = {},
                              const ExactCurveProjection& exactCurveProjection = {});

struct StarVertex {
  struct Incident {
    int polyline = -1;    // index into FeatureGraph::polylines
    bool at_start = true;  // the star vertex is points.front() (else points.back())
  };
  Point3 point{};
  std::vector<Incident> incident;  // two or more polyline ends
  // l_min,i of the thesis: the shortest constrained segment incident to the vertex, i.e.
  // the shortest first (or last) segment of the incident polylines.
  double shortest_incident_length = 0;
};

// The star vertices of `graph`: polyline ends closer than `tolerance` are the same vertex.
// Sorted by position (lexicographic), so the order does not depend on polyline order.
std::vector<StarVertex> findStarVertices(const FeatureGraph& graph, double tolerance);

// Thesis Q1: at every star vertex that is not free (its incident end segments differ in
// length, or one of them ends at another star vertex), a point goes on each incident end
// segment at l_min,i / 3 from the star vertex, so that all segments incident to it are
// equally long and none reaches another star vertex. The point is on the end segment's chord
// (off the exact curve by at most the sampling sagitta; the pipeline snaps mesh vertices onto
// the curve afterwards). `stars` must come from findStarVertices(graph, ...). Curve ids and
// origins are kept; no polyline is added or removed.
FeatureGraph equalizeStarSegments(const FeatureGraph& graph, const std::vector<StarVertex>& stars);

}  // namespace oraclemesh
