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
// polyline leaves the meshed domain (outside every material, or inside a cut). Where a
// polyline has its exact CAD edge (`curves[i]`, may be null or shorter), the check is made on
// that edge: chords of a hole's edge on an outer face cut across the hole, off the domain by
// their sagitta, though the mesh edges end up on the exact edge.
class UserCurve;
FeatureGraph userPolylineFeatures(const std::vector<std::vector<Point3>>& polylines, const HierarchicalOracle& oracle,
                                  double maxSegmentLength,
                                  const std::vector<std::shared_ptr<const UserCurve>>& curves = {});

// Rule Set Q's first step (thesis §3.2.2): splits polylines where they cross or touch one
// another so that every meeting point is an end point shared bitwise by all pieces.
// - A pair with a user polyline meets where the two come closer than `tolerance`; the meeting
//   point is taken on the CAD curve (it lies on the CAD edge).
// - Two CAD curves (sharp edges, junction curves) meet where they come closer than
//   `curveTolerance` (their chords stray from the exact curves by the sampling sagitta) at an
//   angle of at least a degree (nearer to parallel they are tangent, not crossing): there both
//   are split at the middle of the closest points. Where one ends on the other (within
//   100 x curveTolerance: a T), the other is split at that end point. Within
//   `sharedEndClearance` of an end both share, nothing is split: curves leaving a B-rep vertex
//   at a small angle stay close for a while without crossing. Two CAD curves that share a
//   stretch (a segment of one lies on the other: edges of parts in contact along the same
//   arc) are not split against each other. curveTolerance <= 0 leaves CAD pairs alone.
// Pieces keep their fields; curves are renumbered 0, 1, ...
FeatureGraph splitAtCrossings(const FeatureGraph& graph, double tolerance, double curveTolerance = 0,
                              double sharedEndClearance = 0);

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
