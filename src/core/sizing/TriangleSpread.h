#pragma once
// Points spread over a triangle no farther than a spacing apart, where the size samples of a
// face's tessellation are measured. An even grid of ceil(longest / spacing) steps does that
// with about one point per spacing^2 of area on a well-shaped triangle, but puts
// (longest / spacing)^2 / 2 points on a needle of the tessellation (a long edge along a
// fillet) whose area asks for about one per spacing of its length. A needle gets rows of
// points along its longest edge instead, as many as its height needs.
#include <array>
#include <cstddef>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

// Barycentric weights of corners 0 and 1 (corner 2 has the rest) of points of the triangle
// `corners`, the three corners among them, such that every point of the triangle lies within
// spacing / sqrt(3) of one of them, each point once. On a well-shaped triangle they are the
// even grid's, (a / n, b / n) for a from 0 to n and b from 0 to n - a, in that order. The grid
// has at most about `maxPoints` points: past them the spacing is not met.
std::vector<std::array<double, 2>> spreadOverTriangle(const Point3 (&corners)[3], double spacing,
                                                      size_t maxPoints = size_t(1) << 20);

}  // namespace oraclemesh
