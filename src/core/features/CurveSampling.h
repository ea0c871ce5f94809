#pragma once
// Discretisation of exact B-rep curves into feature polylines, shared by the sharp edges and
// the junction curves so both kinds of constrained segment are sampled alike.
#include <BRepAdaptor_Curve.hxx>

#include <vector>

namespace oraclemesh {

// Curve parameters in [first, last], first and last included: arc-length-uniform, segments no
// longer than maxSegmentLength (and at least minSegments), refined by halving until every
// chord is within sagittaTolerance of the curve at its parametric middle.
std::vector<double> polylineParameters(const BRepAdaptor_Curve& curve, double first, double last,
                                       double maxSegmentLength, double sagittaTolerance, int minSegments);

}  // namespace oraclemesh
