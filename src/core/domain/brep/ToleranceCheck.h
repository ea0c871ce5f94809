#pragma once
// Tolerances within the model's scale (internal to domain/brep). OpenCASCADE widens an edge's
// and its vertices' tolerances until the edge "lies on" its faces; on a damaged file (a face
// whose surface lost its placement) that is millimetres, and every later step believes it:
// corners of one edge become one point (a sharp-edge polyline that runs out and back), the
// classifier takes the wide band as surface. Such a shape is refused before meshing.
#include <TopoDS_Solid.hxx>

#include <string>
#include <vector>

namespace oraclemesh {

// Largest tolerance allowed, relative to the solid's bounding-box diagonal. The shared real
// models stay under 2e-4 (U_Joint_2.stp: 0.021 mm on 139 mm); the damaged files seen reach
// 4.5 % (part.step with 3 bytes changed) and 36 % (a box whose plane lost its point).
constexpr double kLargestRelativeTolerance = 0.01;

// InputError starting with `what` naming the edge (or vertex, face) of the largest tolerance
// over kLargestRelativeTolerance of its solid's diagonal: which solid, which edge, where, how
// wide, and the fix.
void requireTolerancesWithinModel(const std::vector<TopoDS_Solid>& solids, const std::string& what);

}  // namespace oraclemesh
