#include "job/EngineRun.h"

#include "features/FeatureSeparation.h"

#include <algorithm>

namespace oraclemesh {

namespace {

// Mesh_3's protecting balls along the features: the job's edge size, lowered where curves run
// close to one another or are short (features/FeatureSeparation), down to 1e-4 of the diagonal,
// and where the sizing field or a gap asks for less.
FeatureEdgeSizes localEdgeSizes(const FeatureGraph& features, const CriteriaTable& table, double diagonal) {
  FeatureEdgeSizes sizes = localFeatureEdgeSizes(features, table.strictest(&MaterialCriteria::edge_size),
                                                 1e-4 * diagonal, 1e-9 * diagonal);
  if (table.varies())
    for (size_t i = 0; i < sizes.at_points.size() && i < features.polylines.size(); ++i)
      for (size_t k = 0; k < sizes.at_points[i].size() && k < features.polylines[i].points.size(); ++k)
        sizes.at_points[i][k] = std::min(sizes.at_points[i][k], table.edgeSizeAt(features.polylines[i].points[k]));
  return sizes;
}

// The CGAL Mesh_3 settings of a job.
Mesh3Options mesh3Options(const JobSpec& job, const CriteriaTable& criteria) {
  Mesh3Options options;
  options.criteria = criteria;
  options.perturb = job.perturb;
  options.exude = job.exude;
  options.optimize_time_limit = job.optimize_time_limit;
  options.sliver_bound = job.sliver_bound;
  options.max_vertices = job.max_vertices;
  options.seed = job.seed;
  return options;
}

}  // namespace

EngineRun runMesh3Engine(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& criteria,
                         const FeatureGraph& features, const RunControl& control, PhaseClock& clock) {
  EngineRun result;
  Mesh3Options options = mesh3Options(job, criteria);
  FeatureEdgeSizes edgeSizes = localEdgeSizes(features, criteria, oracle.diagonal());
  options.feature_edge_sizes = edgeSizes.at_points;
  Mesh3Statistics stats;
  result.mesh = meshWithCgalMesh3(oracle, features, options, control, &stats);
  clock.finish("mesh3");  // the engine's total; its phases are reported beside it
  for (const auto& [phase, sec] : stats.seconds) clock.seconds["mesh3_" + phase] = sec;
  result.report.seeds_on_boundary = stats.initial_points;
  result.report.protecting_ball_vertices = stats.protecting_balls;
  result.report.mesh3 = Mesh3EngineReport{std::move(stats), std::move(edgeSizes)};
  return result;
}

}  // namespace oraclemesh
