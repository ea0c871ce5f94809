#pragma once
// Reading STL (ASCII and binary), OBJ (both by CGAL) and ASCII OFF (our own reader) files into
// points and triangles, with every check that needs no geometry: readable, triangles only,
// indices in range, finite coordinates, counts that fit the file. TriangleSurface checks the geometry afterwards.
// Kept apart from TriangleSurface (which needs CGAL's mesh processing) so that the fuzz
// targets can build it alone.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

struct TriangleSoup {
  std::vector<Point3> points;
  std::vector<std::array<int64_t, 3>> triangles;  // 0-based indices into points
};

// InputError starting with `what` (e.g. "input 'bone' (file 'tibia.stl')") and naming the
// defect and the fix.
TriangleSoup readTriangleSurfaceFile(const std::string& path, const std::string& what);

}  // namespace oraclemesh
