#include "improve/OracleBoundaryPlacement.h"

#include <cmath>

namespace oraclemesh {

OracleBoundaryPlacement::OracleBoundaryPlacement(const TetMesh& mesh, const HierarchicalOracle& oracle,
                                                 const CurveRegistry& curves, const BoundarySnapResult& snap)
    : oracle_(oracle), curves_(curves), snapped_(mesh.points), entry_(snap.vertex_entry), curve_(mesh.vertex_curve) {
  // A vertex the snap left off the model has no place on it to move from.
  for (size_t v = 0; v < entry_.size() && v < snap.distance_kept.size(); ++v)
    if (snap.distance_kept[v] > 0) entry_[v] = -1;
  curve_.resize(snapped_.size(), -1);
  patch_.assign(snapped_.size(), kUnknownPatch);
}

std::optional<Point3> OracleBoundaryPlacement::ontoSurface(int64_t v, const Point3& q) const {
  if (v < 0 || v >= static_cast<int64_t>(entry_.size()) || entry_[v] < 0) return std::nullopt;
  const Source& source = *oracle_.entries()[entry_[v]].source;
  // The vertex stays on its own patch (a B-rep face): the neighbouring face across an edge too
  // smooth to be a feature curve is another piece of the CAD, which it may not wander onto.
  if (patch_[v] == kUnknownPatch) patch_[v] = source.project(snapped_[v]).patch;
  const BoundaryProjection onto = source.projectOnPatch(q, patch_[v]);
  if (!std::isfinite(onto.distance)) return std::nullopt;
  return onto.point;
}

std::optional<Point3> OracleBoundaryPlacement::ontoCurve(int64_t v, const Point3& q) const {
  if (v < 0 || v >= static_cast<int64_t>(curve_.size()) || curve_[v] < 0) return std::nullopt;
  const BoundaryProjection onto = curves_.project(curve_[v], q);
  if (!std::isfinite(onto.distance)) return std::nullopt;
  return onto.point;
}

}  // namespace oraclemesh
