#pragma once
// Constrained segments (thesis §3): polylines the mesh must contain as chains of edges.
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

struct FeaturePolyline {
  std::vector<Point3> points;  // at least two; ends are exact curve ends or clip points
  int curve = -1;              // curve id, unique within the FeatureGraph
  int source = -1;             // index of the oracle entry the curve belongs to
  int edge = -1;               // B-rep edge index within that source (-1: not a B-rep edge)
  int junction = -1;           // index into JunctionCurves when the polyline runs along a
                               // junction curve (source and edge are then -1)
  int user = -1;               // index into the job's features.polylines for a user polyline
};

// A triangle surface's sharp edges (TriangleSurfaceSharpEdges): a source and none of edge,
// junction and user; the polyline is its own exact curve.
inline bool isTriangleSurfaceEdge(const FeaturePolyline& pl) {
  return pl.source >= 0 && pl.edge < 0 && pl.junction < 0 && pl.user < 0;
}

struct FeatureGraph {
  std::vector<FeaturePolyline> polylines;
  bool empty() const { return polylines.empty(); }
};

}  // namespace oraclemesh
