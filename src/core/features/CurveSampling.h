#pragma once
// Discretisation of exact B-rep curves into feature polylines, shared by the sharp edges and
// the junction curves so both kinds of constrained segment are sampled alike.
#include <BRepAdaptor_Curve.hxx>

#include <algorithm>
#include <vector>

namespace oraclemesh {

// Curve parameters in [first, last], first and last included: arc-length-uniform, segments no
// longer than maxSegmentLength (and at least minSegments), refined by halving until every
// chord is within sagittaTolerance of the curve at its parametric middle.
std::vector<double> polylineParameters(const BRepAdaptor_Curve& curve, double first, double last,
                                       double maxSegmentLength, double sagittaTolerance, int minSegments);

// How far the chords of a feature polyline may stray from their curve, for every kind of
// feature curve of a model of bounding-box diagonal `diagonal`. Mesh_3 puts its feature vertices
// on the chords and the pipeline then moves them onto the exact curve; where curves meet at a
// few degrees (part.step: 2.5 degrees) such a move can fold a tet, and the node stays off the
// curve (reported). 1e-5 of the diagonal left none off on part.step, but Mesh_3's protecting
// ball refinement slows down with the number of polyline points (presse_asm.step did not
// finish in 19 minutes), so the bound stays at 1e-3 of the diagonal.
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

}  // namespace oraclemesh
