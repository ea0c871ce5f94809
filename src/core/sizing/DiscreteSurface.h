#pragma once
// The boundary of an input that has no exact faces, as triangles the sizing field can measure
// (issue 16: triangle surfaces and voxel images get sizes from their discrete curvature and
// thickness, as B-rep faces do from their exact ones): a triangle surface's own triangles, an
// image label's voxel faces smoothed into a surface near the oracle's.
#include <array>
#include <cstdint>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

class RunControl;
class Source;

struct DiscreteSurface {
  std::vector<Point3> points;
  std::vector<std::array<int64_t, 3>> triangles;  // outward
  // How far the triangles may lie from the input's boundary (0 for a triangle surface, which
  // is its triangles), for the gap widths that fall within it of the contact tolerance.
  double deviation = 0;
  // The smallest size curvature may ask for: an image's voxel, for it resolves nothing finer
  // (0 for a triangle surface).
  double resolution = 0;
  // 1: the curvature is measured per sheet over each point's edges (cornerCurvatures); more: the
  // surface is a smoothed one, without sharp edges, measured over the points this many edges away.
  int curvature_rings = 1;
};

// Whether `source` is a triangle surface or an image label (cheap: no surface is built).
bool hasDiscreteSurface(const Source& source);

// Empty (no triangles) for a source that is neither a triangle surface nor an image label.
// `control` is checked between the smoothing passes of an image's surface.
DiscreteSurface discreteSurfaceOf(const Source& source, const RunControl& control);

// Per triangle of `surface`, at each of its corners p: the largest normal curvature of its
// sheet there along the sheet's edges from p, 2 |n . (q - p)| / |q - p|^2 for each edge p-q
// (exact on a sphere or a circle through p and q with the normal n at p). The sheet is made of
// the triangles around p whose normals are within `sharpAngleDeg` of the triangle's, so an edge
// sharper than that (a feature, kept by the sharp edges) is no curvature, and a point on such an
// edge has one curvature per side; n is the mean of their normals, weighted by their angles at p.
std::vector<std::array<double, 3>> cornerCurvatures(const DiscreteSurface& surface, double sharpAngleDeg);

}  // namespace oraclemesh
