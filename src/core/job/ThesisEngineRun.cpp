#include "job/EngineRun.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>

#include "Error.h"
#include "job/PoorElements.h"
#include "mesh/Topology.h"
#include "mesh/Writers.h"
#include "refine/PlanarFacets.h"
#include "refine/ThesisEngine.h"

namespace oraclemesh {

namespace {

// A refinement stopped by a limit leaves its mesh so far next to each output file
// (mesh.vtu -> mesh.partial.vtu) for inspection; returns what to add to the error message.
std::string writePartialMesh(const JobSpec& job, TetMesh& partial) {
  if (partial.tets.empty() || job.output_files.empty()) return "";
  partial.boundary = extractBoundary(partial);
  std::string written;
  for (const std::string& file : job.output_files) {
    std::filesystem::path path(file);
    path.replace_extension(".partial" + path.extension().string());
    try {
      writeMeshFile(path.string(), partial);
      written += (written.empty() ? "" : ", ") + path.string();
    } catch (const Error&) {
      // The limit is the error to report; an unwritable partial mesh only goes unmentioned.
    }
  }
  return written.empty() ? "" : " (the mesh so far, " + std::to_string(partial.tets.size()) + " tets, is in " + written + ")";
}

// The dihedral angle the thesis engine's sliver removal (the sliver rule, then perturbation) aims for:
// 5 degrees above optimize.sliver_bound. The perturber stops as soon as every tet clears its
// bound, and slight moves after it (vertices it left off the faces going back in the snap)
// may cost a little; with the margin the final mesh clears the job's bound (default 10: demo
// assembly and implant_in_bone 15 degrees). Rule S aims as high as perturbation: below it,
// the perturber spends seconds on lifting what the sliver rule left (demo: 20 s instead of 0.3 s).
double thesisSliverBound(const JobSpec& job) {
  constexpr double kMarginDeg = 5, kMaxDeg = 69;  // below the regular tetrahedron's 70.5
  return std::min(job.sliver_bound + kMarginDeg, kMaxDeg);
}

}  // namespace

EngineRun runThesisEngine(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& criteria,
                          const AssembledFeatures& assembled, const RunControl& control, PhaseClock& clock,
                          std::vector<std::string>& warnings) {
  const FeatureGraph& features = assembled.graph;
  const std::vector<SmallInputAngle>& smallAngles = assembled.small_angles;
  const CurveRegistry& curves = assembled.curves;
  EngineRun result;
  RuleSetTOptions options;
  options.criteria = criteria;
  options.assignment = job.material_assignment;
  options.initial_points = job.initial_points;
  options.max_vertices = job.max_vertices;
  options.seed = job.seed;
  std::vector<SkippedPlanarFace> skippedPlanarFaces;
  if (job.planar_faces) options.planar_faces = findPlanarFaces(oracle, job.sharp_angle_deg, &skippedPlanarFaces);
  // Where the terminator rule may leave cells: curves along small dihedral angles and along
  // wedges that touching inputs close, and the points where curves meet at small angles or
  // cones end.
  for (const SmallInputAngle& a : smallAngles) {
    if (a.kind != "dihedral" && a.kind != "contact") {
      options.small_angle_points.push_back(a.location);
      continue;
    }
    for (int curve : curvesOfSmallAngle(a, features, oracle)) options.small_angle_curves.push_back(curve);
  }
  // Sliver removal (optimize.perturb) starts in the engine: the sliver rule, after T1-T3, lifts the
  // slivers perturbation cannot (next to segment vertices, which it keeps fixed: on the demo
  // assembly perturbation alone stops at 3.6 degrees).
  options.sliver_dihedral_deg = job.perturb ? thesisSliverBound(job) : 0;
  // Segment vertices go onto the curves, so the snap leaves them where they are (moving them
  // by the chord's sagitta took implant_in_bone (a) from 13.7 degrees before the snap to 7.9
  // after it).
  options.onto_curve = [&](int curve, const Point3& p) { return curves.ontoCurve(curve, p); };
  RuleSetTStatistics stats;
  try {
    result.mesh = meshWithRuleSetT(oracle, features, options, control, &stats);
  } catch (const LimitError& e) {
    throw LimitError(e.what() + writePartialMesh(job, stats.partial));
  }
  clock.finish("thesis");  // the engine's total; its phases are reported beside it
  for (const auto& [phase, sec] : stats.seconds) clock.seconds["thesis_" + phase] = sec;
  // Rule Set T bounds radius-edge ratios, which slivers satisfy: they are removed by CGAL's
  // perturbation, as in the Mesh_3 engine, on a C3T3 rebuilt from this mesh. It must run
  // before the snap, while the mesh is still the Delaunay triangulation of its points.
  // Exudation is left out: it weights non-feature vertices, and without Mesh_3's protecting
  // balls on the segments that can drop a constrained subsegment from the triangulation (the
  // demo assembly lost 6 of 537); perturbation alone keeps them all and reached the same
  // minimum dihedral angle there.
  // Perturbation stops as soon as every cell clears its bound, so when rules S and P (the
  // engine's own vertex moves) left none under that bound it would only scan the mesh;
  // skipping it also skips rebuilding the Mesh_3 complex (implant_in_bone (a): 0.7 s of a
  // 2.6 s job).
  const bool slivers_left = stats.slivers_left_total > 0;
  // A feature edge the engine's mesh lost (a subsegment left no Delaunay edge) makes the
  // complex impossible to rebuild; the pipeline's final check names that edge instead.
  if (job.perturb && slivers_left && featureEdgesNotTetEdges(result.mesh) == 0) {
    control.report("sliver removal", 0);
    Mesh3Options sliverRemoval = mesh3Options(job, criteria);
    sliverRemoval.exude = false;
    sliverRemoval.sliver_bound = thesisSliverBound(job);
    Mesh3Statistics optimizeStats;
    // CGAL's perturber keeps segment vertices fixed but, with no protecting balls in the
    // rebuilt complex, may move a neighbour into a subsegment's diametral ball and flip the
    // subsegment away (part.step with sharp edges: 1 of 621). Rule Set T's guarantee that
    // every constrained segment is a chain of mesh edges wins over the angles: the mesh
    // before perturbation is kept then.
    TetMesh beforePerturbation = result.mesh;
    optimizeTetMeshWithCgal(result.mesh, oracle, sliverRemoval, control, &optimizeStats);
    // The perturber moved and renumbered vertices: only those still where the engine put
    // them keep the boundary entry it recorded.
    carryBoundaryEntries(beforePerturbation, result.mesh);
    for (const auto& [phase, sec] : optimizeStats.seconds) clock.seconds["thesis_" + phase] = sec;
    const int64_t dropped = featureEdgesNotTetEdges(result.mesh) +
                            std::max<int64_t>(0, static_cast<int64_t>(beforePerturbation.feature_edges.size()) -
                                                     static_cast<int64_t>(result.mesh.feature_edges.size()));
    if (dropped > 0) {
      result.mesh = std::move(beforePerturbation);
      warnings.push_back("CGAL's sliver perturbation took " + std::to_string(dropped) +
                         " constrained subsegment(s) out of the mesh, so the mesh before it is kept (slivers the sliver rule "
                         "and rule P left stay: see report.thesis.slivers_left)");
    }
    clock.finish("sliver_removal");
  }
  result.report.seeds_on_boundary = stats.initial_points;
  if (job.planar_faces && stats.planar.missing > 0)
    warnings.push_back(std::to_string(stats.planar.missing) +
                       " triangle(s) of planar faces are not mesh facets (see report.thesis.planar_faces)");
  if (!stats.left.empty())
    warnings.push_back(std::to_string(stats.elements_left_total) +
                       " element(s) still violate their criteria (see report.thesis.elements_left for where and "
                       "why; small input angles are the usual cause)");
  result.report.thesis = ThesisEngineReport{std::move(stats), job.planar_faces, std::move(skippedPlanarFaces)};
  return result;
}

}  // namespace oraclemesh
