#pragma once
// The user's own constrained segments (job features.polylines; in FreeCAD, selected edges and
// sketches), and the Rule Set Q step every mix of feature kinds needs (thesis §3.3): curves may
// meet only at polyline ends, so crossings become shared vertices.
#include <memory>
#include <string>
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

// One FeaturePolyline per segment of a user polyline (`user` = the polyline's index,
// source/edge/junction -1), so every given point stays a mesh vertex; split into pieces no
// longer than maxSegmentLength. Throws InputError naming features.polylines[i] when a
// polyline leaves the meshed domain (outside every material, or inside a cut).
FeatureGraph userPolylineFeatures(const std::vector<std::vector<Point3>>& polylines, const HierarchicalOracle& oracle,
                                  double maxSegmentLength);

// Splits polylines where they cross or touch one another (closer than `tolerance`) so that
// every meeting point is an end point shared bitwise by all pieces. Only pairs with a user
// polyline are examined: sharp edges and junction curves already meet at their ends by
// construction. The crossing point is taken on the non-user curve (it lies on the CAD edge).
// Pieces keep their fields; curves are renumbered 0, 1, ...
FeatureGraph splitAtCrossings(const FeatureGraph& graph, double tolerance);

// Nearest point of a polyline (the user curve is the polyline itself).
Point3 nearestOnPolyline(const std::vector<Point3>& polyline, const Point3& p);

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
