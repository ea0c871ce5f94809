#pragma once
// The CGAL Mesh_3 engine behind a plain interface: no CGAL type crosses this header, so
// only Mesh3Engine.cpp pays the Mesh_3 compile time.
#include <map>
#include <string>
#include <vector>

#include "MeshCriteria.h"
#include "RunControl.h"
#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

struct Mesh3Options {
  CriteriaTable criteria;
  bool perturb = true;
  bool exude = true;
  double optimize_time_limit = 0;   // seconds per optimizer; 0 = none (results stay deterministic)
  double sliver_bound = 10;         // dihedral angle (degrees) the optimizers try to reach
  int64_t max_vertices = 0;         // 0 = no limit
  unsigned seed = 0;                // Mesh_3's random choices (bisection start points)
  // Edge size (protecting-ball radius) at every point of every feature polyline, indexed like
  // FeatureGraph::polylines[i].points[k] (features/FeatureSeparation); empty = the criteria's
  // edge_size everywhere.
  std::vector<std::vector<double>> feature_edge_sizes;
};

struct Mesh3Statistics {
  std::map<std::string, double> seconds;  // per phase
  int64_t initial_points = 0;             // surface seeds inserted by us
  int64_t protecting_balls = 0;
  double radius_edge_ratio_used = 0;      // Mesh_3 takes one bound for all materials
  double facet_angle_used = 0;
};

// Meshes the composite domain of `oracle`, protecting `features` (empty = featureless).
// Vertices are left where Mesh_3 put them (within its bisection error of the boundary);
// putting them exactly on the CAD is the pipeline's job. Throws LimitError, Cancelled.
TetMesh meshWithCgalMesh3(const HierarchicalOracle& oracle, const FeatureGraph& features,
                          const Mesh3Options& options, const RunControl& control,
                          Mesh3Statistics* statistics = nullptr);

}  // namespace oraclemesh
