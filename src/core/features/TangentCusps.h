#pragma once
// Two feature curves that leave a vertex tangentially (a nut's chamfer cone pinching to a point
// between its bearing circle and a flat, a line tangent to an arc) bound a face that is
// narrower than any element near the vertex: its width grows with the square of the distance.
// With both curves as chains of mesh edges, the tets at the vertex span that width and are flat
// (under 2 degrees at presse_asm's nut), and refinement chases the cusp down to the terminator
// length. No mesh whose elements keep some least size there can have both curves and good
// tets, so near the cusp one curve stands for both: the shorter curve's polyline starts on the
// longer one's chain at the sample where the two part by a given share of the local edge size,
// and the face between them is left out over that stretch (it is narrower than that share of an
// element there). The curves then leave that point at an angle that grows with the share (a
// quarter of the edge size across a chord of at most the edge size: 14 degrees or more), which
// the engines treat as any small input angle.
#include <functional>
#include <string>
#include <vector>

#include "Geometry.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

// One cusp where a curve was trimmed: the vertex, the curve that now starts on the other one,
// where it starts, and how far apart the two exact curves were there.
struct TangentCusp {
  Point3 vertex{};
  int trimmed_curve = -1;   // curve ids of the input graph
  int kept_curve = -1;
  int source = -1;          // the trimmed polyline's oracle entry and B-rep edge (FeaturePolyline)
  int trimmed_edge = -1, kept_edge = -1;
  std::string input;        // the trimmed curve's input name (left to the caller)
  Point3 parting_point{};   // the kept curve's sample the trimmed curve now starts from
  Point3 resumes_at{};      // the trimmed curve's first sample kept: a chord joins it to parting_point
  double merged_length = 0; // the trimmed curve's length left to the kept curve's chain
  double width = 0;         // distance of resumes_at from the kept curve's chain
};

// Leaving direction of a polyline at its front (atBack = false) or back: a unit vector pointing
// into the polyline (InputAngles.h's leavingDirection gives it from the exact curve).
using LeavingDirection = std::function<Point3(const FeaturePolyline&, bool atBack)>;

// For every pair of polylines sharing an end point at which they leave at under
// `tangentAngleDeg` (their exact tangents), the shorter one (by length; the higher curve id
// when equal; never a user polyline, which is kept whole) loses the samples within
// `widthPerEdgeSize` x edgeSize(sample) of the longer one's chain from that end on, and starts
// at the longer one's sample nearest to the last sample lost (where the shorter one stays that
// close all along, the longer one gives way instead, against the shorter one's chain); the
// kept one is split there into two polylines so that the meeting is a shared end (the step
// before Rule Set Q asks for that). A curve is trimmed at most once per end, never by a curve
// it trims elsewhere, and never to fewer than two points (then the pair is left as it is).
// Curves are renumbered 0, 1, ... in polyline order; `cusps` receives what was done, with the
// input graph's curve ids.
FeatureGraph mergeTangentCusps(const FeatureGraph& graph, const LeavingDirection& leaving,
                               const std::function<double(const Point3&)>& edgeSize, double tangentAngleDeg,
                               double widthPerEdgeSize, std::vector<TangentCusp>* cusps = nullptr);

}  // namespace oraclemesh
