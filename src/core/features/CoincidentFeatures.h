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
// Two samplings of one curve (an arc shared by parts in contact, with B-rep vertices at other
// places; a junction curve along a sharp edge) have different chords that stray up to the
// sampling sagitta from each other: with `curveTolerance` > 0 (twice that sagitta), a piece also
// runs along an earlier B-rep edge polyline when its ends lie on that exact edge and its chord
// midpoint within curveTolerance of it (along an earlier junction polyline: all three within
// curveTolerance of its chords), and the earlier polyline's vertices on this one's exact edge
// split it there. Only within the earlier polyline's ends: its exact edge goes on beyond them
// (the next piece of a split edge) where the polyline does not.
FeatureGraph removeCoincidentFeatures(const FeatureGraph& graph, const HierarchicalOracle& oracle,
                                      double curveTolerance = 0);

}  // namespace oraclemesh
