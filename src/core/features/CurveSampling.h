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
// few degrees (part.step: 2.5 degrees) a move of a few percent of the edge size inverts a tet,
// so the vertex is left off the curve. 1e-5 of the diagonal keeps every such move harmless (no
// vertex left off on part.step, against 22 up to 0.05 mm with 2 % of the edge size) for a few
// times more polyline points.
inline double featureSagittaTolerance(double maxSegmentLength, double diagonal) {
  return std::min(0.02 * maxSegmentLength, 1e-3 * diagonal);
}

}  // namespace oraclemesh
