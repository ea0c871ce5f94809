#pragma once
// How the improvement stage puts a moved boundary vertex back onto the model: onto the CAD face
// (or triangle surface, image boundary) it lies on, or onto its feature curve. The stage knows
// only the mesh; the pipeline gives it this from the oracle and the curve registry
// (improve/OracleBoundaryPlacement). Without one, vertices on curved faces and curves stay put.
#include <cstdint>
#include <optional>

#include "Geometry.h"

namespace oraclemesh {

class BoundaryPlacement {
 public:
  virtual ~BoundaryPlacement() = default;
  // The point nearest to q of the surface piece vertex v lies on (for a B-rep, v's own face);
  // nothing when v is not on such a piece or q's nearest point lies on another piece.
  virtual std::optional<Point3> ontoSurface(int64_t v, const Point3& q) const = 0;
  // The point nearest to q of v's feature curve; nothing when v has no curve with geometry.
  virtual std::optional<Point3> ontoCurve(int64_t v, const Point3& q) const = 0;
};

}  // namespace oraclemesh
