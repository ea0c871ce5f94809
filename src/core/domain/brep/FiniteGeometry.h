#pragma once
// Every number of a shape's geometry checked finite before anything evaluates it (internal to
// domain/brep). A NaN pole or vertex would otherwise flow through the tessellation into CGAL's
// exact predicates, whose conversion to rationals stops the process (SIGFPE in GMP).
#include <TopoDS_Shape.hxx>

#include <string>

namespace oraclemesh {

// Vertices, tolerances, edge ranges, locations, the 3D curves, the curves on faces and the
// surfaces (poles, weights, knots, axes, radii, offsets, trims) and stored triangulations. An
// InputError starting with `what` names the first non-finite item found.
void requireFiniteGeometry(const TopoDS_Shape& shape, const std::string& what);

}  // namespace oraclemesh
