#pragma once
// The two refinement engines as a job runs them: their options from the job, the engine
// itself, and what the report says about the run. Thesis engine: refine/ThesisEngine, then
// CGAL's sliver perturbation (ThesisEngineRun.cpp); Mesh_3 engine: cgal/Mesh3Engine with
// local protecting-ball sizes (Mesh3EngineRun.cpp).
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

// Rule Set T with the small input angles, planar faces and curves of `features`, then CGAL's
// perturbation where slivers are left. Phases "thesis", "thesis_<engine phase>" and
// "sliver_removal" on `clock`; its warnings are appended. Throws LimitError (naming the
// partial mesh it wrote next to the output files), Cancelled.
EngineRun runThesisEngine(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& criteria,
                          const AssembledFeatures& features, const RunControl& control, PhaseClock& clock,
                          std::vector<std::string>& warnings);

// Mesh_3 with protecting balls along `features`. Phases "mesh3" and "mesh3_<engine phase>".
EngineRun runMesh3Engine(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& criteria,
                         const FeatureGraph& features, const RunControl& control, PhaseClock& clock);

// The CGAL Mesh_3 settings of a job: the Mesh_3 engine's, and the sliver removal every
// engine's mesh goes through.
Mesh3Options mesh3Options(const JobSpec& job, const CriteriaTable& criteria);

}  // namespace oraclemesh
