#pragma once
// Sharp edges of a triangle surface input (STL, OBJ, OFF, a FreeCAD Mesh) as constrained
// segments: the counterpart of BrepSharpEdges for inputs without exact faces, so that the
// edges of an exported box or a machined part kept as triangles stay edges of the mesh.
#include <functional>

#include "domain/TriangleSurface.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

// Polylines along the surface's edges whose two triangles' outward normals differ by more than
// `sharpAngleDeg`. They run between corners: vertices where the number of sharp edges is not
// two, or where the line turns by more than `sharpAngleDeg`; a closed line of sharp edges with
// no corner is one polyline from and back to its lowest-numbered vertex.
// Every surface vertex on them is a polyline point (the surface's edges are the curve: a point
// on a chord is on the surface), and segments longer than the local edge size are split
// evenly: `maxSegmentLength`, or `localSegmentLength` at the segment's middle when given and
// smaller. `source` = sourceIndex, edge / junction / user = -1, curve ids 0, 1, ...
FeatureGraph extractTriangleSurfaceSharpEdges(const TriangleSurface& surface, int sourceIndex, double sharpAngleDeg,
                                              double maxSegmentLength,
                                              const std::function<double(const Point3&)>& localSegmentLength = {});

}  // namespace oraclemesh
