#pragma once
// Where a model may lie so that doubles still resolve it. The oracle's tolerances are 1e-9 of
// the bounding-box diagonal; a coordinate x is resolved to x * 2.2e-16, so beyond 1e6
// diagonals from the origin that tolerance is under about four units in the last place, and
// the exact predicates see points that rounding has already moved or merged (a sphere of
// radius 5 at 1e20 collapses to one point and crashes the triangulation). The absolute bounds
// keep the squared lengths the core computes in doubles away from overflow and underflow.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "Error.h"
#include "Geometry.h"

namespace oraclemesh {

inline constexpr double kMaxDistanceInDiagonals = 1e6;
inline constexpr double kMaxCoordinate = 1e100;
inline constexpr double kMinDiagonal = 1e-100;

// InputError starting with `what` when the box is not finite, too large or too small, or lies
// too far from the origin for its size.
inline void requireCoordinateRange(const Bbox& box, const std::string& what) {
  if (box.empty()) return;
  double far = 0;
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(box.min[k]) || !std::isfinite(box.max[k]))
      throw InputError(what + " has a coordinate that is not a finite number: the data is damaged; export it again");
    far = std::max({far, std::abs(box.min[k]), std::abs(box.max[k])});
  }
  const double size = box.diagonal();
  std::ostringstream text;
  text.precision(3);
  // At the bound itself too: OpenCASCADE bounds an unbounded curve or surface there (a line
  // whose direction a damaged STEP file gave as a zero vector).
  if (far >= kMaxCoordinate) {
    text << what << " has coordinates of " << far << " model units, as far as the mesher computes with ("
         << kMaxCoordinate << "): an unbounded curve or surface (a damaged file: check it with Part > Check "
         << "geometry or export it again) or a model in the wrong units (scale it to millimetres or metres)";
    throw InputError(text.str());
  }
  if (far > kMaxDistanceInDiagonals * size) {
    text << what << " lies " << far << " model units from the origin but is only " << size
         << " across: so far away doubles cannot resolve it (at most " << kMaxDistanceInDiagonals
         << " times its size); move the model near the origin (its Placement in FreeCAD) before meshing";
    throw InputError(text.str());
  }
  if (!(size >= kMinDiagonal)) {
    text << what << " is only " << size << " model units across: scale the model to millimetres or metres";
    throw InputError(text.str());
  }
}

}  // namespace oraclemesh
