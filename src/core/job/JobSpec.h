#pragma once
// The job contract (src/README.md, "The job contract"): what the CLI, Python and FreeCAD all
// send. Parsing validates everything a user can get wrong before any geometry is touched.
#include <nlohmann/json_fwd.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "Geometry.h"
#include "MeshCriteria.h"
#include "domain/HierarchicalOracle.h"
#include "mesh/InterfaceKinds.h"

namespace oraclemesh {

// The refinement engine: Rule Set T (refine/ThesisEngine) or CGAL Mesh_3 (cgal/Mesh3Engine).
enum class Engine { Thesis, Cgal };

// What runJob does when the finished mesh fails its self-check (job/MeshSelfCheck.h): a part
// missing volume or split into pieces. Job key "checks".
enum class MeshCheckMode { Warn, Error };

// The job's names for them ("thesis", "cgal"; "circumcenter", "barycenter"), as parsed and as
// printed back in the report.
const char* engineName(Engine engine);
const char* materialAssignmentName(MaterialAssignment assignment);

struct InputSpec {
  enum class Kind { File, BrepText, Sphere, Surface, Image };
  std::string name;
  Kind kind = Kind::File;
  std::string file;       // Kind::File, resolved against the job's base directory
  std::string brep_text;  // Kind::BrepText
  Point3 center{};        // Kind::Sphere
  double radius = 0;
  std::vector<Point3> surface_points;                   // Kind::Surface
  std::vector<std::array<int64_t, 3>> surface_triangles;  // 0-based indices into surface_points
  // B-rep files and text: "solids": "separate" (default) makes each solid its own input
  // "<name>#k" in file order; "together" keeps them as one input.
  bool solids_together = false;
  // "materials": [m1, m2, ...]: material of each solid in file order (separate solids only;
  // the count is checked against the file when it is read). Empty: every solid gets `material`.
  std::vector<int> solid_materials;
  std::string image;                   // Kind::Image: NRRD file, resolved like `file`
  std::map<int, int> image_materials;  // Kind::Image: "materials" {label: material id}
  Role role = Role::Material;
  int material = 0;                    // not Kind::Image

  // The material ids this input can give (per-solid materials, the image's mapped
  // materials, or `material`).
  std::vector<int> materials() const;
};

// Criteria as the user wrote them; unset values are filled from the model size later.
struct CriteriaSpec {
  std::optional<double> cell_size, cell_radius_edge_ratio, facet_size, facet_distance, facet_angle, edge_size;
};

// "interfaces": how touching parts are joined, per pair of parts named as in the report
// (report.interfaces[i].parts). The names are checked against the parts once the inputs are
// loaded (job/InterfaceSettings); here only the form.
struct InterfacePairSpec {
  std::array<std::string, 2> between;
  InterfaceBehaviour behaviour;  // master_material is filled when the names are resolved
  std::string master;            // "master": one of `between`, or "" (the writer chooses)
};

struct InterfacesSpec {
  InterfaceKind default_kind = InterfaceKind::Bonded;
  // "contact_stiffness": the slope for every contact pair that gives none; 0 = not given.
  double default_contact_stiffness = 0;
  std::vector<InterfacePairSpec> pairs;
};

struct JobSpec {
  std::vector<InputSpec> inputs;  // highest priority first
  CriteriaSpec default_criteria;
  std::map<int, CriteriaSpec> material_criteria;
  // "criteria.fineness": a preset of sizing/Fineness.h, or "off" (constant sizes only); unset
  // is kDefaultFineness.
  std::optional<std::string> fineness;
  bool features = true;
  double sharp_angle_deg = 30;
  bool junctions = true;  // curves where two inputs' boundaries cross become features
  // features.planar_faces (thesis engine): planar B-rep faces bounded by sharp edges are meshed
  // as planes, their 2D Delaunay triangles recovered as facets (thesis §4.1).
  bool planar_faces = false;
  // features.polylines: the user's own constrained segments (e.g. load-patch outlines drawn
  // on a face, a crack front). Each has at least two distinct consecutive points.
  std::vector<std::vector<Point3>> user_polylines;
  // Per user polyline: BREP text of the CAD edge it was sampled from ({"points": [...],
  // "brep": "..."}, as FreeCAD sends its extra edges), else empty. Mesh nodes along such a
  // polyline go onto the exact edge instead of the chords.
  std::vector<std::string> user_polyline_curves;
  // "thesis" (Rule Set T) or "cgal" (Mesh_3). Thesis is the default since it beat Mesh_3 on
  // the refine benchmark (issue 7); Mesh_3 stays one setting away for the inputs it handles
  // better (protecting balls terminate for any input angle).
  Engine engine = Engine::Thesis;
  // Thesis engine only: which point of a cell decides its material ("circumcenter", Pons
  // 2007, or "barycenter", thesis §4.1), and points inserted before refinement.
  MaterialAssignment material_assignment = MaterialAssignment::Circumcenter;
  std::vector<Point3> initial_points;
  int element_order = 2;
  // Sliver removal: Mesh_3 engine, CGAL's perturbation and exudation; thesis engine, its
  // sliver rule and rule P (perturb; exude is Mesh_3's only).
  bool perturb = true;
  bool exude = true;
  bool improve = true;  // the improvement stage after the snap (improve/MeshImprovement)
  // No time limit by default: a time-limited optimizer gives machine-dependent meshes.
  double optimize_time_limit = 0;
  double sliver_bound = 10;  // dihedral angle (degrees) sliver removal aims for (thesis: + 5)
  // "contact_tolerance": parts closer than this touch and are bonded, parts farther apart stay
  // apart (the gap sizing, the self-check's joined-parts test). Unset: max(1e-6 of the
  // diagonal, the inputs' shape tolerances, a STEP file's declared uncertainty)
  // (job/ContactTolerance.h).
  std::optional<double> contact_tolerance;
  // "cad_uncertainty": what the file the inputs were imported from declares as its
  // uncertainty (a STEP file's UNCERTAINTY_MEASURE_WITH_UNIT), for B-rep text inputs that no
  // longer carry it (the workbench sends it); the default contact tolerance is at least this.
  double cad_uncertainty = 0;
  int64_t max_vertices = 5'000'000;
  double time_limit = 3600;
  unsigned seed = 0;
  // A mesh that is not the model (a part short of volume, split or joined) is no result.
  MeshCheckMode checks = MeshCheckMode::Error;
  InterfacesSpec interfaces;
  std::vector<std::string> output_files;  // resolved against the base directory
  std::string report_file;

  // Throws InputError with a message naming the offending key or input and the fix.
  static JobSpec fromJson(const nlohmann::json& job, const std::string& baseDirectory);
  static JobSpec fromJsonText(const std::string& text, const std::string& baseDirectory);
};

}  // namespace oraclemesh
