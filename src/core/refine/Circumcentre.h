#pragma once
// A Delaunay cell's circumcentre that is always a finite point.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace oraclemesh::refine {

// The floating-point formula divides by the cell's orientation determinant, which rounds to
// zero or overflows on a nearly flat cell: its result is then infinite or NaN, and a dual
// edge from it would send NaN points to the oracle. Only then is the centre computed again
// with exact rationals; a finite floating-point centre is returned unchanged. An exact centre
// beyond the range of doubles gives the point `farAway` from corner a in its exact direction
// (far outside every input, as the centre is); an exactly flat cell, which has no sphere, the
// point `farAway` along the normal of its largest face.
CGAL::Epick::Point_3 finiteCircumcentre(const CGAL::Epick::Point_3& a, const CGAL::Epick::Point_3& b,
                                        const CGAL::Epick::Point_3& c, const CGAL::Epick::Point_3& d,
                                        double farAway);

}  // namespace oraclemesh::refine
