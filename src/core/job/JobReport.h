#pragma once
// The job report as typed parts, filled by the phases of runJob, and the one place that turns
// them into the report's JSON (report.json; JobResult::report). The JSON keys are part of the
// job contract (src/README.md), read by the tests, FreeCAD and users' scripts.
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "MeshCriteria.h"
#include "cgal/Mesh3Engine.h"
#include "domain/HierarchicalOracle.h"
#include "features/FeatureSeparation.h"
#include "features/InputAngles.h"
#include "features/TangentCusps.h"
#include "job/ContactTolerance.h"
#include "job/JobSpec.h"
#include "job/MeshSelfCheck.h"
#include "improve/MeshImprovement.h"
#include "job/PoorElements.h"
#include "mesh/BoundarySnap.h"
#include "mesh/InterfaceConstraints.h"
#include "mesh/InterfaceSplit.h"
#include "mesh/Quality.h"
#include "mesh/Surfaces.h"
#include "mesh/Topology.h"
#include "refine/ThesisEngine.h"
#include "sizing/GeometrySizes.h"

namespace oraclemesh {

// report.inputs[i]: oracle entry i.
struct InputReport {
  std::string name;   // the entry's own name ("<input>#k" for the k-th solid of a file)
  std::string input;  // the job input it came from
  std::string kind;   // "B-rep solid", "triangle surface", "image region", ...
  Role role = Role::Material;
  int material = 0;
  double source_volume = 0;
};

// report.features: the constrained segments the engine got.
struct FeatureReport {
  bool enabled = true;
  double sharp_angle_deg = 0;
  bool junctions = true;
  int64_t sharp_edge_polylines = 0, junction_polylines = 0, user_polylines = 0;
  size_t polylines = 0;
  int64_t crossing_pieces = 0;  // polylines added by splitting at crossings (Rule Set Q)
  int64_t star_vertices = 0;
  std::vector<TangentCusp> tangent_cusps;  // where one curve stands for two near a tangent vertex
};

// report.thesis: what Rule Set T did (engine "thesis").
struct ThesisEngineReport {
  RuleSetTStatistics statistics;                      // its `seconds` go to report.seconds
  bool planar_faces = false;                          // features.planar_faces was asked for
  std::vector<SkippedPlanarFace> skipped_planar_faces;
};

// report.criteria.*_applied: what Mesh_3 made of the criteria (engine "cgal").
struct Mesh3EngineReport {
  Mesh3Statistics statistics;  // its `seconds` go to report.seconds
  FeatureEdgeSizes feature_edge_sizes;
};

// What either engine reports; exactly one of thesis and mesh3 is set.
struct EngineReport {
  int64_t seeds_on_boundary = 0;
  int64_t protecting_ball_vertices = 0;  // Mesh_3 only
  std::optional<ThesisEngineReport> thesis;
  std::optional<Mesh3EngineReport> mesh3;
};

// report.boundary_snap.
struct SnapReport {
  BoundarySnapStatistics statistics;
  double min_dihedral_before_deg = 0;  // what the snap costs in quality
};

// report.counts, with QualityReport's tets per material.
struct MeshCounts {
  size_t vertices = 0, tets = 0, boundary_triangles = 0, feature_edges = 0;
};

// Part names per material id: the names of the material inputs (solids) with that id, joined
// by '+' when several share it. Interfaces and exteriors are named after these.
MaterialNames partNames(const std::vector<InputReport>& inputs);

// report.interfaces / report.exteriors: one entry per meshSurfaces surface.
struct SurfaceReport {
  int material = 0, other_material = 0;  // other_material 0: an exterior
  std::string name;                      // the INP *SURFACE and FreeCAD face group name
  double area = 0;
  size_t triangles = 0;
};

std::vector<SurfaceReport> describeSurfaces(const std::vector<MeshSurface>& surfaces, const MaterialNames& names);

struct ImprovementReport {
  bool enabled = false;  // optimize.improve
  ImprovementStats stats;
  PoorElements poor;  // after the stage
};

struct JobReport {
  std::string version;
  Engine engine = Engine::Thesis;
  MaterialAssignment material_assignment = MaterialAssignment::Circumcenter;  // thesis engine only
  std::vector<InputReport> inputs;
  double bbox_diagonal = 0;
  CriteriaTable criteria;
  std::string fineness = "off";  // the sizing field's preset (criteria.fineness), or "off"
  ContactTolerance contact_tolerance;
  std::vector<PartGap> gaps;  // between entries, from the sizing field (fineness set)
  FeatureReport features;
  std::vector<SmallInputAngle> small_input_angles;
  double small_input_angle_limit_deg = 0;
  EngineReport engine_run;
  SnapReport boundary_snap;
  ImprovementReport improve;  // the stage after the snap, before second order
  int element_order = 2;
  int64_t second_order_straight_fallbacks = 0;  // element_order 2 only
  MeshCounts counts;
  QualityReport quality;
  ConformityReport conformity;
  MeshCheckMode checks = MeshCheckMode::Warn;
  MeshSelfCheck self_check;
  std::vector<SurfaceReport> surfaces;  // interfaces and exteriors, as meshSurfaces orders them
  InterfacePlan interfaces;             // the job's "interfaces" by material ids
  std::vector<InterfaceConstraint> interface_constraints;  // ties and contacts as the INP has them
  InterfaceSplitStats interface_split;
  std::vector<std::string> warnings;  // in the order the phases found them
  std::map<std::string, double> seconds;
};

// Appends the warnings the finished mesh gives: boundary nodes the snap kept off the CAD faces,
// inverted tets, a failed conformity check.
void addMeshWarnings(JobReport& report);

// The report of a finished job ("status": "done").
nlohmann::json reportJson(const JobReport& report);

// How a job ended early; the report's "status".
enum class JobEnd {
  Stopped,      // "stopped": a limit (time, vertices, memory)
  Cancelled,    // "cancelled"
  InputError,   // "input_error": the job or an input is unusable
  FailedCheck,  // "failed_check": the mesh was made and the self-check refused it
  Error,        // "error": anything else
};

// The report of a job that ended early, written to output.report all the same so that the
// user sees where the time went and what was found: the status, the error message, the phase
// it ended in ("stopped_in", as report.seconds names phases), the seconds per phase up to
// there, the warnings, and what the finished phases filled in (inputs, criteria and gaps
// after "load", features and small input angles after "features"). A failed check has the
// whole report.
nlohmann::json unfinishedReportJson(const JobReport& report, const std::map<std::string, double>& seconds, JobEnd end,
                                    const std::string& message, const std::string& phase);

// Writes report.dump(2) to `path`; Error when the file cannot be written.
void writeReportFile(const std::string& path, const nlohmann::json& report);

}  // namespace oraclemesh
