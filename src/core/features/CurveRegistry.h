#pragma once
// Where each feature curve of a job came from, so that points can be put onto the exact curve
// behind its polyline: a B-rep edge of an oracle entry, a junction curve (two inputs'
// boundaries crossing), a user polyline with, when the job gave one, its exact CAD edge, or
// the edges of a triangle surface (the polyline is the curve).
// The thesis engine's segment vertices, the boundary snap and the second-order mid nodes all
// go onto the curves through it.
#include <memory>
#include <unordered_map>
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"
#include "features/JunctionCurves.h"
#include "features/UserPolylines.h"

namespace oraclemesh {

class CurveRegistry {
 public:
  // `oracle` must outlive the registry (B-rep edges are looked up in its entries).
  explicit CurveRegistry(const HierarchicalOracle& oracle) : oracle_(&oracle) {}

  // Curve `curve` runs along B-rep edge `edge` of oracle entry `entry`.
  void addBrepEdge(int curve, int entry, int edge);
  // Curve `curve` runs along junction curve `junction` of `junctions` (kept alive here).
  void addJunction(int curve, std::shared_ptr<const JunctionCurves> junctions, int junction);
  // Curve `curve` is (part of) the user polyline `polyline`; `exact` is the CAD edge it was
  // sampled from, or null (the polyline is then the curve).
  void addUserPolyline(int curve, std::shared_ptr<const std::vector<Point3>> polyline,
                       std::shared_ptr<const UserCurve> exact);
  // Registers every polyline of `graph` by its origin fields (FeaturePolyline::source, ::edge,
  // ::junction, ::user; isTriangleSurfaceEdge: the polyline is its own curve).
  // `userPolylines` and `userCurves` are indexed by FeaturePolyline::user (userCurves may hold
  // nulls).
  void addPolylines(const FeatureGraph& graph, const std::shared_ptr<const JunctionCurves>& junctions,
                    const std::vector<std::shared_ptr<const std::vector<Point3>>>& userPolylines,
                    const std::vector<std::shared_ptr<const UserCurve>>& userCurves);

  bool contains(int curve) const { return origins_.count(curve) > 0; }
  // The oracle entry a registered curve belongs to (a B-rep edge's or a triangle surface's
  // entry), -1 for junction and user curves and for curves not registered.
  int entryOf(int curve) const;
  // The point of curve `curve` nearest to p. Infinite distance when the curve is not
  // registered or has no exact geometry to project onto.
  BoundaryProjection project(int curve, const Point3& p) const;
  // project(curve, p).point, or p itself where that projection has nothing.
  Point3 ontoCurve(int curve, const Point3& p) const;

 private:
  struct Origin {
    int entry = -1;
    int edge = -1;
    int junction = -1;                                 // junction curve index, then entry = edge = -1
    std::shared_ptr<const JunctionCurves> junctions;    // owns the junction edges for the run
    std::shared_ptr<const std::vector<Point3>> user;    // the job's polyline for a user polyline
    std::shared_ptr<const UserCurve> user_curve;        // its exact CAD edge, when the job gave one
  };
  const HierarchicalOracle* oracle_;
  std::unordered_map<int, Origin> origins_;
};

}  // namespace oraclemesh
