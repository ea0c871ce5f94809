#pragma once
// Tolerances within the model's scale, and kept (internal to domain/brep). OpenCASCADE widens
// an edge's and its vertices' tolerances until the edge "lies on" its faces; on a damaged file
// (a face whose surface lost its placement) that is millimetres, and every later step
// believes it: corners of one edge become one point (a sharp-edge polyline that runs out and
// back), the classifier takes the wide band as surface. A BREP file is read as written, so a
// damaged number leaves an edge whose curve ends far from its vertices, where OpenCASCADE's
// exact classifier then spends seconds per point. Such shapes are refused before meshing.
#include <TopoDS_Solid.hxx>

#include <string>
#include <vector>

namespace oraclemesh {

// Largest tolerance allowed, relative to the solid's bounding-box diagonal. The shared real
// models stay under 2e-4 (U_Joint_2.stp: 0.021 mm on 139 mm); the damaged files seen reach
// 3.9 % (part.step with 3 bytes changed) and 16 % (a box whose plane lost its point; of the
// box as widened by that tolerance).
constexpr double kLargestRelativeTolerance = 0.01;

// A curve end may lie this far beyond its vertex's tolerance sphere before the edge counts as
// broken: twice the tolerance, and at least this fraction of the solid's diagonal (the shared
// models: gaps up to the tolerance, at most 6e-6 of the diagonal; the damaged BREP seen, 5 %).
constexpr double kLargestRelativeEndGap = 1e-4;

// InputError starting with `what` naming the edge (or vertex, face) of the largest tolerance
// over kLargestRelativeTolerance of its solid's diagonal, or the first edge whose curve ends
// farther from its vertex than the tolerance allows: which solid, which edge, where, how far,
// and the fix.
void requireConsistentTolerances(const std::vector<TopoDS_Solid>& solids, const std::string& what);

}  // namespace oraclemesh
