#pragma once
// The user's own constrained segments (job features.polylines; in FreeCAD, selected edges and
// sketches), with the exact CAD edges they may come with. Where they cross other curves is
// split by splitAtCrossings (features/RuleSetQ.h).
#include <memory>
#include <string>
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

// One FeaturePolyline per segment of a user polyline (`user` = the polyline's index,
// source/edge/junction -1), so every given point stays a mesh vertex; split into pieces no
// longer than maxSegmentLength. Throws InputError naming features.polylines[i] when a
// polyline leaves the meshed domain (outside every material, or inside a cut). Where a
// polyline has its exact CAD edge (`curves[i]`, may be null or shorter), the check is made on
// that edge: chords of a hole's edge on an outer face cut across the hole, off the domain by
// their sagitta, though the mesh edges end up on the exact edge.
class UserCurve;
FeatureGraph userPolylineFeatures(const std::vector<std::vector<Point3>>& polylines, const HierarchicalOracle& oracle,
                                  double maxSegmentLength,
                                  const std::vector<std::shared_ptr<const UserCurve>>& curves = {});

// The exact CAD edge a user polyline was sampled from (FreeCAD's extra edges): the polyline's
// points lie on it, and mesh nodes between them are put onto it rather than onto the chords.
class UserCurve {
 public:
  // BREP text holding exactly one edge; InputError naming `where` otherwise.
  static std::shared_ptr<const UserCurve> fromBrep(const std::string& text, const std::string& where);
  ~UserCurve();
  // Nearest point of the edge (its ends included).
  Point3 nearest(const Point3& p) const;

 private:
  struct Data;
  explicit UserCurve(std::unique_ptr<Data> data);
  std::unique_ptr<Data> data_;
};

}  // namespace oraclemesh
