#pragma once
// The two refinement engines as a job runs them: their options from the job, the engine
// itself, and what the report says about the run. Thesis engine: refine/ThesisEngine, whose
// sliver rule and rule P are its sliver removal (ThesisEngineRun.cpp); Mesh_3 engine:
// cgal/Mesh3Engine with local protecting-ball sizes and CGAL's perturbation and exudation
// (Mesh3EngineRun.cpp).
#include <string>
#include <vector>

#include "MeshCriteria.h"
#include "RunControl.h"
#include "cgal/Mesh3Engine.h"
#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"
#include "job/FeatureAssembly.h"
#include "job/JobReport.h"
#include "job/JobSpec.h"
#include "job/PhaseClock.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

struct EngineRun {
  TetMesh mesh;  // as the engine (and sliver removal) left it: boundary nodes not yet snapped
  EngineReport report;
};

// Rule Set T with the small input angles, planar faces and curves of `features`, with the
// sliver rule and rule P when optimize.perturb is on. Phases "thesis" and
// "thesis_<engine phase>" on `clock`; its warnings are appended. Throws LimitError (naming the
// partial mesh it wrote next to the output files), Cancelled.
EngineRun runThesisEngine(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& criteria,
                          const AssembledFeatures& features, const RunControl& control, PhaseClock& clock,
                          std::vector<std::string>& warnings);

// Mesh_3 with protecting balls along `features`. Phases "mesh3" and "mesh3_<engine phase>".
EngineRun runMesh3Engine(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& criteria,
                         const FeatureGraph& features, const RunControl& control, PhaseClock& clock);

}  // namespace oraclemesh
