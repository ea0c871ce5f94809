#pragma once
// The improvement stage's BoundaryPlacement for a mesh the boundary snap has put on the model:
// a surface vertex goes back onto the boundary of the oracle entry the snap put it on (for a
// B-rep, onto the same face), a curve vertex onto its feature curve.
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "features/CurveRegistry.h"
#include "improve/BoundaryPlacement.h"
#include "mesh/BoundarySnap.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

class OracleBoundaryPlacement final : public BoundaryPlacement {
 public:
  // `oracle` and `curves` must outlive this; the mesh's points are read now (each vertex's
  // face is the one under its place after the snap).
  OracleBoundaryPlacement(const TetMesh& mesh, const HierarchicalOracle& oracle, const CurveRegistry& curves,
                          const BoundarySnapResult& snap);

  std::optional<Point3> ontoSurface(int64_t v, const Point3& q) const override;
  std::optional<Point3> ontoCurve(int64_t v, const Point3& q) const override;

 private:
  static constexpr int kUnknownPatch = -2;
  const HierarchicalOracle& oracle_;
  const CurveRegistry& curves_;
  std::vector<Point3> snapped_;     // where each vertex was after the snap
  std::vector<int> entry_;          // the entry whose boundary it is on, -1 none
  std::vector<int> curve_;          // its feature curve, -1 none
  mutable std::vector<int> patch_;  // its B-rep face, found on first use
};

}  // namespace oraclemesh
