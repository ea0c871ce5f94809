#pragma once
// Sharp B-rep edges as constrained segments (thesis §3), and their clipping to the part of
// the composite boundary that survives the priority composition.
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include <functional>

#include "domain/BrepTopology.h"
#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

// Polylines along the edges of `solid` whose two faces meet at an angle sharper than
// `sharpAngleDeg` (the angle between the outward face normals exceeds it somewhere along the
// edge). Seams, degenerated edges and tangent edges are left out; an edge with one face is
// kept. Each polyline runs from the exact B-rep vertex to the exact B-rep vertex (shared
// vertices give bitwise-equal end points) through points on the exact curve, with segments
// no longer than `maxSegmentLength` and a small chord sagitta; next to a vertex where two
// sharp edges leave at under 15 degrees (exact tangents) the chords of each also stay within
// a quarter of the gap to the other (down to 1e-4 of the diagonal).
// Curve ids are sourceIndex * kCurvesPerSource + edge index: unique and deterministic even
// when the graphs of several solids are merged. `edge` is the 0-based edge index.
// sagittaTolerance > 0 replaces featureSagittaTolerance (CurveSampling.h) as the chord bound.
// localSegmentLength, when given (the sizing field's edge size), grades the segments along
// each edge by it (gradedPolylineParameters), below maxSegmentLength.
FeatureGraph extractSharpEdges(const BrepTopology& solid, int sourceIndex, double sharpAngleDeg,
                               double maxSegmentLength, double sagittaTolerance = 0,
                               const std::function<double(const Point3&)>& localSegmentLength = {});

// Outward unit normal of `face` at curve parameter u of `edge` (through the edge's pcurve on
// that face); false where the surface is singular (apex, pole).
bool outwardNormalAlongEdge(const TopoDS_Edge& edge, const TopoDS_Face& face, double u, gp_Vec& normal);

// Outward unit normal of `face` at p, a point on it (found by projection onto its surface);
// false where the surface is singular or the projection fails.
bool outwardNormalAt(const TopoDS_Face& face, const gp_Pnt& p, gp_Vec& normal);

constexpr int kCurvesPerSource = 1000000;

// The parts of `graph` that lie on the composite boundary of `oracle`: a polyline of entry i
// is dropped where it is strictly inside a higher-priority entry; a `cut` entry's polyline is
// kept only where the region just beyond the cut is material of a lower entry; a material
// entry's polyline is dropped where it is strictly inside a lower entry of the same material
// (no interface there). Cuts are located by bisection to ~1e-12 of the diagonal and put back
// on the B-rep edge, so that new end points lie on the edge and on the cutting surface.
// Every piece gets a new curve id (0, 1, ... in output order); `source` and `edge` are kept.
FeatureGraph clipToCompositeBoundary(const FeatureGraph& graph, const HierarchicalOracle& oracle);

}  // namespace oraclemesh
