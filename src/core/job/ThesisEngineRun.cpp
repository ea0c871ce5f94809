#include "job/EngineRun.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>

#include "Error.h"
#include "features/SharpEdgeFaces.h"
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

// The dihedral angle the thesis engine's sliver removal (the sliver rule, then rule P) aims for:
// 5 degrees above optimize.sliver_bound. The snap and the improvement stage after the engine
// move vertices slightly; with the margin the final mesh clears the job's bound where the
// engine reached its target (default 10: demo assembly and implant_in_bone 15 degrees).
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
  std::vector<int> dihedralCurves;
  for (const SmallInputAngle& a : smallAngles) {
    if (a.kind != "dihedral" && a.kind != "contact") {
      options.small_angle_points.push_back(a.location);
      continue;
    }
    for (int curve : curvesOfSmallAngle(a, features, oracle)) {
      options.small_angle_curves.push_back(curve);
      if (a.kind == "dihedral") dihedralCurves.push_back(curve);
    }
  }
  options.faces_meeting_at_small_dihedrals = facesMeetingAlongCurves(oracle, features, dihedralCurves);
  // Sliver removal (optimize.perturb) is the engine's own: the sliver rule after T1-T3, then
  // rule P's vertex moves. What they leave goes to the improvement stage after the snap.
  options.sliver_dihedral_deg = job.perturb ? thesisSliverBound(job) : 0;
  // Segment vertices go onto the curves, so the snap leaves them where they are (moving them
  // by the chord's sagitta took implant_in_bone (a) from 13.7 degrees before the snap to 7.9
  // after it).
  options.onto_curve = [&](int curve, const Point3& p) { return curves.ontoCurve(curve, p); };
  RuleSetTStatistics stats;
  // The engine's phases beside its total; also those a limit stopped, for the stopped job's report.
  const auto bookEnginePhases = [&] {
    for (const auto& [phase, sec] : stats.seconds) clock.seconds["thesis_" + phase] = sec;
  };
  try {
    result.mesh = meshWithRuleSetT(oracle, features, options, control, &stats);
  } catch (const LimitError& e) {
    bookEnginePhases();
    throw LimitError(e.what() + writePartialMesh(job, stats.partial));
  }
  clock.finish("thesis");
  bookEnginePhases();
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
