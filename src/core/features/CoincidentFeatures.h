#pragma once
// Touching and overlapping parts of an assembly share faces and edges. Two copies of one
// curve, or an edge buried in a face of a higher-priority input, would make Mesh_3 protect
// the same place twice (it never ends) or keep a crease that is not there.
#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

// Drops the parts of each polyline that run along a polyline listed before it (higher
// priority first: clipToCompositeBoundary keeps entry order), splitting it exactly at the
// earlier polyline's vertices; then drops the parts of a lower entry's polyline that lie on a
// higher entry's boundary where the composite boundary is flat (no crease). Fields other than
// the points (curve, source, edge, junction) are kept on every piece; curves are renumbered.
FeatureGraph removeCoincidentFeatures(const FeatureGraph& graph, const HierarchicalOracle& oracle);

}  // namespace oraclemesh
