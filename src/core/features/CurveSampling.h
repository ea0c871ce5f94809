#pragma once
// Discretisation of exact B-rep curves into feature polylines, shared by the sharp edges and
// the junction curves so both kinds of constrained segment are sampled alike.
#include <BRepAdaptor_Curve.hxx>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include <algorithm>
#include <functional>
#include <vector>

namespace oraclemesh {

// Curve parameters in [first, last], first and last included: arc-length-uniform, segments no
// longer than maxSegmentLength (and at least minSegments), refined by halving until every
// chord is within sagittaTolerance of the curve at its parametric middle.
std::vector<double> polylineParameters(const BRepAdaptor_Curve& curve, double first, double last,
                                       double maxSegmentLength, double sagittaTolerance, int minSegments);

// The same with segments that follow a local length instead of one length for the whole curve:
// about localLength (at most maxSegmentLength) where each lies, so a long edge that ends at a
// short one is split finely only near it. The segment count is the integral of 1 / length
// along the curve, rounded up (at least minSegments), and the points share that integral
// equally, so neighbouring segments differ as smoothly as the local length does. Chords
// further than sagittaTolerance from the curve are then halved.
std::vector<double> gradedPolylineParameters(const BRepAdaptor_Curve& curve, double first, double last,
                                             const std::function<double(const gp_Pnt&)>& localLength,
                                             double maxSegmentLength, double sagittaTolerance, int minSegments);

// How far the chords of a feature polyline may stray from their curve, for every kind of
// feature curve of a model of bounding-box diagonal `diagonal`. Mesh_3 puts its feature vertices
// on the chords and the pipeline then moves them onto the exact curve; where curves meet at a
// few degrees (part.step) such a move can fold a tet. Sampling everything to 1e-5 of the
// diagonal avoids that, but Mesh_3's protecting-ball refinement slows down with the number of
// polyline points (presse_asm.step did not finish in 19 minutes), so the bound stays at 1e-3
// of the diagonal and polylines are refined only near narrow corners (refineNearCurves).
inline double featureSagittaTolerance(double maxSegmentLength, double diagonal) {
  return std::min(0.02 * maxSegmentLength, 1e-3 * diagonal);
}

// The same bound for the thesis engine, whose constrained segments are the polylines'
// segments: every sample becomes a mesh vertex and T1 only ever splits, so a sampling finer
// than the surface approximation asks for refines the mesh along every curved edge (with a
// radius-edge bound of 1.1 that spreads far). Chords stay within half the smallest
// facet_distance of their curve, and within 5 % of the segment length so that moving the split
// points from the chords onto the curves after refinement stays small against the elements.
inline double thesisSagittaTolerance(double maxSegmentLength, double facetDistance) {
  return std::min(0.05 * maxSegmentLength, 0.5 * facetDistance);
}

// Splits the segments of `params` (increasing curve parameters, as polylineParameters gives
// them) at their parametric middle until the chord's sagitta is within
// max(floorTolerance, localTolerance(curve point at the segment's middle)). Used where another
// feature curve runs close by: a chord must then stay a small fraction of the gap between
// the curves away from its own curve, or moving mesh nodes from the chord onto the curve folds
// the elements in between. floorTolerance > 0 bounds the work.
void refineParameters(const BRepAdaptor_Curve& curve, std::vector<double>& params,
                      const std::function<double(const gp_Pnt&)>& localTolerance, double floorTolerance);

// Unit tangent of the curve at parameter u, from BRepLProp (so also where the first derivative
// vanishes but a higher one does not); false where the curve has no tangent there.
bool unitTangent(const BRepAdaptor_Curve& curve, double u, gp_Vec& tangent);

}  // namespace oraclemesh
