#include "job/Pipeline.h"

#include <algorithm>
#include <exception>
#include <new>
#include <string>
#include <utility>

#include "Error.h"
#include "domain/HierarchicalOracle.h"
#include "improve/MeshImprovement.h"
#include "improve/OracleBoundaryPlacement.h"
#include "job/ContactTolerance.h"
#include "job/EngineRun.h"
#include "job/FeatureAssembly.h"
#include "job/InputChecks.h"
#include "job/InputLoading.h"
#include "job/InterfaceSettings.h"
#include "job/JobReport.h"
#include "job/MeshSelfCheck.h"
#include "job/PoorElements.h"
#include "job/PhaseClock.h"
#include "job/ResolvedCriteria.h"
#include "mesh/BoundarySnap.h"
#include "mesh/InterfaceConstraints.h"
#include "mesh/InterfaceSplit.h"
#include "mesh/Quality.h"
#include "mesh/SecondOrder.h"
#include "mesh/Topology.h"
#include "mesh/Writers.h"

#ifndef ORACLEMESH_VERSION
#define ORACLEMESH_VERSION "dev"
#endif

namespace oraclemesh {

const char* version() { return ORACLEMESH_VERSION; }

namespace {

// The phases of a job, in order. `phase` follows them (the names report.seconds books them
// under), so that a job ending with an error can say where.
JobResult runPhases(const JobSpec& job, const RunControl& control, PhaseClock& clock, JobReport& report,
                    std::string& phase) {
  report.version = version();
  report.engine = job.engine;
  report.material_assignment = job.material_assignment;
  report.element_order = job.element_order;

  phase = "load";
  control.report("load", 0);
  LoadedInputs inputs = loadInputs(job, control);
  report.warnings = std::move(inputs.warnings);
  const HierarchicalOracle oracle(std::move(inputs.entries));
  checkCutsLeaveMaterial(oracle);
  const double diagonal = oracle.diagonal();
  if (diagonal > 1e5)
    report.warnings.push_back("the model is over 100 m across (" + std::to_string(diagonal) +
                              " model units): FreeCAD works in mm, check the units of the inputs");
  CriteriaTable criteria = resolveCriteria(job, diagonal);
  report.contact_tolerance = contactTolerance(job, oracle, inputs);
  criteria.contact_tolerance = report.contact_tolerance.value;
  report.gaps = attachSizeField(criteria, job, oracle, report.contact_tolerance.value, control);
  checkExpectedSize(job, oracle, criteria);
  report.inputs = describeInputs(oracle, inputs);
  report.bbox_diagonal = diagonal;
  report.criteria = criteria;
  if (criteria.field) report.fineness = jobFineness(job)->name;
  // Part names are known now: a misspelt one in "interfaces" stops the job before meshing.
  const MaterialNames names = partNames(report.inputs);
  report.interfaces = resolveInterfaces(job.interfaces, names);
  clock.finish("load");

  phase = "features";
  control.report("features", 0);
  const AssembledFeatures features = assembleFeatures(job, oracle, criteria, control, report.warnings);
  report.features = describeFeatures(job, features);
  report.small_input_angles = features.small_angles;
  report.small_input_angle_limit_deg = kSmallInputAngleLimitDeg;
  clock.finish("features");
  control.checkpoint();

  phase = job.engine == Engine::Thesis ? "thesis" : "mesh3";
  EngineRun run = [&] {
    try {
      return job.engine == Engine::Thesis
                 ? runThesisEngine(job, oracle, criteria, features, control, clock, report.warnings)
                 : runMesh3Engine(job, oracle, criteria, features.graph, control, clock);
    } catch (const NoTetrahedraError& e) {
      throw InputError(e.what() + whatTheInputsEnclose(job, oracle));
    }
  }();
  TetMesh& mesh = run.mesh;
  report.engine_run = std::move(run.report);

  phase = "snap";
  control.report("snap", 0);
  mesh.boundary = extractBoundary(mesh);
  // What the snap costs in quality (each engine leaves some boundary vertices off the faces).
  report.boundary_snap.min_dihedral_before_deg = measureQuality(mesh).min_dihedral;
  BoundarySnapResult snap = snapBoundaryVertices(mesh, oracle, features.curves, control);
  report.boundary_snap.statistics = snap.statistics;
  clock.finish("snap");

  // After the snap (which moves vertices) and before mid nodes are placed on the final topology.
  phase = "improve";
  control.report("improve", 0);
  const OracleBoundaryPlacement placement(mesh, oracle, features.curves, snap);
  ImprovementOptions improvement;
  improvement.time_limit = job.optimize_time_limit;
  improvement.placement = &placement;
  improvement.sizes.edge = [&criteria](const Point3& p) { return criteria.edgeSizeAt(p); };
  improvement.sizes.facet = [&criteria](int material, const Point3& p) {
    return criteria.facetSizeAt(material, p);
  };
  improvement.sizes.cell = [&criteria](int material, const Point3& p) { return criteria.cellSizeAt(material, p); };
  improvement.sizes.cell_ratio = [&criteria](int material) { return criteria.of(material).cell_radius_edge_ratio; };
  report.improve.enabled = job.improve;
  if (job.improve) {
    std::vector<int64_t> previousIndex;
    report.improve.stats = improveMesh(mesh, improvement, control, &previousIndex);
    snap.renumber(previousIndex);
  }
  report.improve.poor = findPoorElements(mesh, report.small_input_angles, features.graph, oracle, improvement.sizes.edge);
  clock.finish("improve");

  if (job.element_order == 2) {
    phase = "second_order";
    control.report("second order", 0);
    report.second_order_straight_fallbacks = makeSecondOrderOnGeometry(mesh, oracle, features.curves, snap.vertex_entry);
    clock.finish("second_order");
  }

  phase = "interfaces";
  // Surfaces from the shared-node mesh, both sides of every pair that is not bonded; the split
  // keeps tet indices, so their faces stay valid after it.
  std::vector<MeshSurface> surfaces = meshSurfaces(mesh, report.interfaces);
  for (std::string& warning : interfaceWarnings(report.interfaces, surfaces, names))
    report.warnings.push_back(std::move(warning));
  report.interface_split = splitInterfaces(mesh, report.interfaces);
  for (std::string& warning : keptJoinedWarnings(report.interfaces, report.interface_split, names))
    report.warnings.push_back(std::move(warning));
  report.interface_constraints = interfaceConstraints(mesh, surfaces, names, report.interfaces);
  clock.finish("interfaces");

  // The final checks. A feature edge that is no tet edge is an error, never a mesh returned.
  requireFeatureEdgesInTets(mesh);
  report.quality = measureQuality(mesh);
  report.conformity = checkConformity(mesh);
  report.counts = {mesh.points.size(), mesh.tets.size(), mesh.boundary.size(), mesh.feature_edges.size()};
  report.surfaces = describeSurfaces(surfaces, names);
  addMeshWarnings(report);

  phase = "check";
  control.report("check", 0);
  report.checks = job.checks;
  // Nodes the snap had to leave off the CAD are that far from their part where it touches
  // another: allowed at those nodes only.
  report.self_check = checkMeshAgainstInputs(mesh, oracle, report.quality.volume_per_material,
                                             report.contact_tolerance.value, snap.distance_kept,
                                             criteria.bonded_wedges.get());
  clock.finish("check");
  report.seconds = clock.seconds;
  if (!report.self_check.problems.empty()) {
    if (job.checks == MeshCheckMode::Error) {
      std::string message = "the mesh does not represent the model";
      for (const std::string& problem : report.self_check.problems) message += "; " + problem;
      throw MeshCheckError(message + " (to keep such a mesh anyway, set \"checks\": \"warn\")");
    }
    for (const std::string& problem : report.self_check.problems) report.warnings.push_back(problem);
  }

  phase = "write";
  control.report("write", 0);
  for (const std::string& path : job.output_files) writeMeshFile(path, mesh, names, surfaces, report.interfaces);
  clock.finish("write");
  report.seconds = clock.seconds;
  JobResult result;
  result.report = reportJson(report);
  if (!job.report_file.empty()) writeReportFile(job.report_file, result.report);
  control.report("done", 1);
  result.mesh = std::move(mesh);
  result.surfaces = std::move(surfaces);
  for (const SurfaceReport& s : report.surfaces) result.surface_names.push_back(s.name);
  return result;
}

// How a job that ended with `error` ended, and the message for its report.
std::pair<JobEnd, std::string> howItEnded(const std::exception& error) {
  if (dynamic_cast<const MeshCheckError*>(&error)) return {JobEnd::FailedCheck, error.what()};
  if (dynamic_cast<const InputError*>(&error)) return {JobEnd::InputError, error.what()};
  if (dynamic_cast<const LimitError*>(&error)) return {JobEnd::Stopped, error.what()};
  if (dynamic_cast<const Cancelled*>(&error)) return {JobEnd::Cancelled, error.what()};
  if (dynamic_cast<const std::bad_alloc*>(&error)) return {JobEnd::Stopped, kOutOfMemoryMessage};
  return {JobEnd::Error, error.what()};
}

// output.report for a job that ended with an error: how it ended and what the phases before
// found (JobReport.h, unfinishedReportJson). The error is what the caller must get, so a
// report that cannot be written is left unwritten.
void writeUnfinishedReport(const JobSpec& job, const JobReport& report, PhaseClock& clock, const std::string& phase,
                           const std::exception& error) {
  if (job.report_file.empty()) return;
  try {
    const auto [end, message] = howItEnded(error);
    if (end != JobEnd::FailedCheck) clock.finish(phase);  // a refused mesh has its check booked
    writeReportFile(job.report_file, unfinishedReportJson(report, clock.seconds, end, message, phase));
  } catch (const std::exception&) {
  }
}

}  // namespace

JobResult runJob(const JobSpec& job, const RunControl& control) {
  PhaseClock clock;
  JobReport report;
  std::string phase;
  try {
    return runPhases(job, control, clock, report, phase);
  } catch (const std::exception& e) {
    writeUnfinishedReport(job, report, clock, phase, e);
    throw;
  }
}

}  // namespace oraclemesh
