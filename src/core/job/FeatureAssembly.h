#pragma once
// The constrained segments of a job, assembled from every kind of feature curve: sharp B-rep
// edges clipped to the composite boundary, junction curves where two inputs' boundaries cross,
// copies along contact arcs merged, the user's polylines; then Rule Set Q's preparation
// (split at crossings, star vertices, Q1 for the Mesh_3 engine). Also where each curve came
// from (CurveRegistry) and the input angles under the thesis' bound.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "MeshCriteria.h"
#include "RunControl.h"
#include "domain/HierarchicalOracle.h"
#include "features/CurveRegistry.h"
#include "features/FeatureGraph.h"
#include "features/InputAngles.h"
#include "features/JunctionCurves.h"
#include "job/JobReport.h"
#include "job/JobSpec.h"

namespace oraclemesh {

// 60 degrees: the thesis' termination bound for Rule Set T (§3.3.2).
constexpr double kSmallInputAngleLimitDeg = 60;

struct AssembledFeatures {
  explicit AssembledFeatures(const HierarchicalOracle& oracle) : curves(oracle) {}
  FeatureGraph graph;  // empty when the job's features are off
  CurveRegistry curves;
  std::shared_ptr<const JunctionCurves> junctions;  // null when junctions are off
  // What the Rule Set Q preparation did, for the report.
  int64_t crossing_pieces = 0;  // polylines added by splitting at crossings
  int64_t star_vertices = 0;
  std::vector<TangentCusp> tangent_cusps;  // where one curve stands for two (TangentCusps.h)
  // Under kSmallInputAngleLimitDeg, smallest first (findSmallInputAngles).
  std::vector<SmallInputAngle> small_angles;
};

// Appends a warning naming the smallest input angle when there are small ones. Throws
// InputError for a user polyline that leaves the domain or whose CAD edge is unreadable.
AssembledFeatures assembleFeatures(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& criteria,
                                   const RunControl& control, std::vector<std::string>& warnings);

// report.features.
FeatureReport describeFeatures(const JobSpec& job, const AssembledFeatures& features);

}  // namespace oraclemesh
