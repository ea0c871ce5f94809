#pragma once
// Local edge sizes for constrained segments. Mesh_3 protects each feature polyline with a chain
// of balls and requires balls of curves that are not neighbours to stay disjoint; where two
// curves run closer than twice the edge size (parts of an assembly in contact along an arc,
// whose edges are sampled independently and so lie a sagitta apart), it shrinks the balls one
// refinement loop at a time and rebuilds the chains, which at a 20 mm edge size and 0.5 mm
// separation does not finish in practice. A size bounded by the local separation from the
// start gives the same protection in one pass.
#include <vector>

#include "features/FeatureGraph.h"

namespace oraclemesh {

struct FeatureEdgeSizes {
  // at_points[i][k]: the edge size at graph.polylines[i].points[k].
  std::vector<std::vector<double>> at_points;
  double smallest = 0;      // over all points (maxSize when nothing bounded it)
  int64_t bounded_points = 0;  // points whose size the separation or curve length lowered
  // The closest pair of curves that bounded a size: where the smallest separation is, and how
  // far apart they are (infinity when no pair came within reach).
  double closest_separation = 0;
  Point3 closest_at{};
};

// The edge size at every polyline point: maxSize (the job's edge size, which stays an upper
// bound), lowered to separation / 2.5 where `separation` is the distance from the point's
// segments to the nearest segment of another curve that is not its neighbour (curves sharing
// an end vertex are neighbours: Mesh_3 separates their balls at the vertex itself), and to a
// third of the polyline's length. Sizes never go below minSize. Deterministic and independent
// of the polyline order.
FeatureEdgeSizes localFeatureEdgeSizes(const FeatureGraph& graph, double maxSize, double minSize,
                                       double endTolerance);

// The size at point p of polyline `points` with per-point sizes `sizes`: linear along the
// nearest segment.
double edgeSizeOnPolyline(const std::vector<Point3>& points, const std::vector<double>& sizes, const Point3& p);

// Distance between segments [a, b] and [c, d].
double segmentDistance(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

}  // namespace oraclemesh
