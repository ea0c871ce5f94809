#include "job/Pipeline.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <set>
#include <unordered_map>

#include "Error.h"
#include "cgal/Mesh3Engine.h"
#include "domain/BrepSolid.h"
#include "domain/LabeledImage.h"
#include "domain/NrrdReader.h"
#include "domain/Sphere.h"
#include "domain/TriangleSurface.h"
#include "features/BrepSharpEdges.h"
#include "features/CoincidentFeatures.h"
#include "features/JunctionCurves.h"
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

using nlohmann::json;

class PhaseClock {
 public:
  void finish(const std::string& phase) {
    const auto now = std::chrono::steady_clock::now();
    seconds[phase] += std::chrono::duration<double>(now - start_).count();
    start_ = now;
  }
  std::map<std::string, double> seconds;

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

SourcePtr loadSource(const InputSpec& in);

// The oracle entries of one input: one, or for an image one per mapped label. The regions of
// one image are disjoint, so their order among themselves does not matter; together they
// take the image's place in the priority list.
std::vector<OracleEntry> loadEntries(const InputSpec& in) {
  if (in.kind != InputSpec::Kind::Image) return {{loadSource(in), in.role, in.material}};
  std::vector<OracleEntry> entries;
  const auto image = readNrrdLabels(in.image, in.name);
  for (auto& [region, material] : makeImageRegions(image, in.image_materials, in.name))
    entries.push_back({region, Role::Material, material});
  return entries;
}

SourcePtr loadSource(const InputSpec& in) {
  switch (in.kind) {
    case InputSpec::Kind::File: {
      std::string ext = std::filesystem::path(in.file).extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
      if (ext == ".stl" || ext == ".obj" || ext == ".off") return TriangleSurface::fromFile(in.file, in.name);
      return BrepSolid::fromFile(in.file, in.name);
    }
    case InputSpec::Kind::BrepText:
      return BrepSolid::fromBrepText(in.brep_text, in.name);
    case InputSpec::Kind::Sphere:
      return std::make_shared<Sphere>(in.center, in.radius, in.name);
    case InputSpec::Kind::Image:
      break;  // several sources: loadEntries
  }
  throw InputError("input '" + in.name + "' has an unknown kind");
}

MaterialCriteria resolve(const CriteriaSpec& spec, const MaterialCriteria& fallback) {
  MaterialCriteria c = fallback;
  if (spec.cell_size) c.cell_size = *spec.cell_size;
  if (spec.cell_radius_edge_ratio) c.cell_radius_edge_ratio = *spec.cell_radius_edge_ratio;
  if (spec.facet_size) c.facet_size = *spec.facet_size;
  if (spec.facet_distance) c.facet_distance = *spec.facet_distance;
  if (spec.facet_angle) c.facet_angle = *spec.facet_angle;
  if (spec.edge_size) c.edge_size = *spec.edge_size;
  return c;
}

// Unset sizes follow the model: a user who gives nothing gets a coarse but sound mesh.
CriteriaTable resolveCriteria(const JobSpec& job, double diagonal) {
  CriteriaTable table;
  MaterialCriteria base;
  const CriteriaSpec& d = job.default_criteria;
  base.cell_size = d.cell_size.value_or(diagonal / 15);
  base.facet_size = d.facet_size.value_or(base.cell_size);
  base.facet_distance = d.facet_distance.value_or(base.facet_size / 10);
  base.cell_radius_edge_ratio = d.cell_radius_edge_ratio.value_or(2);
  base.facet_angle = d.facet_angle.value_or(25);
  base.edge_size = d.edge_size.value_or(base.facet_size / 2);
  table.defaults = base;

  std::set<int> materials;
  for (const InputSpec& in : job.inputs)
    for (int id : in.materials()) materials.insert(id);
  for (const auto& [id, spec] : job.material_criteria)
    if (!materials.count(id))
      throw InputError("criteria.materials names material " + std::to_string(id) +
                       " but no input has that material: fix the id or remove the entry");
  for (int id : materials) {
    auto it = job.material_criteria.find(id);
    table.per_material[id] = it == job.material_criteria.end() ? base : resolve(it->second, base);
  }
  return table;
}

// Refuse up front what would blow the vertex limit: a tet whose circumradius is near the
// bound has about 0.11 r^3 of volume and a mesh has about six tets per vertex.
void checkExpectedSize(const JobSpec& job, const std::vector<OracleEntry>& entries, const CriteriaTable& table) {
  double expected = 0;
  for (const OracleEntry& e : entries) {
    if (e.role != Role::Material) continue;
    const double r = table.of(e.material).cell_size;
    expected += e.source->volume() / (0.66 * r * r * r);
  }
  if (expected > static_cast<double>(job.max_vertices))
    throw InputError("the sizes asked for would give about " + std::to_string(static_cast<int64_t>(expected)) +
                     " vertices, more than limits.max_vertices = " + std::to_string(job.max_vertices) +
                     ": raise cell_size (check the model units: FreeCAD works in mm) or raise limits.max_vertices");
}

struct CurveOrigin {
  int entry = -1;
  int edge = -1;
  int junction = -1;                               // junction curve index, then entry = edge = -1
  std::shared_ptr<const JunctionCurves> junctions;  // owns the junction edges for the run
};

FeatureGraph buildFeatures(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& table,
                           const RunControl& control, std::unordered_map<int, CurveOrigin>& origins) {
  FeatureGraph all;
  if (!job.features) return all;
  double edgeSize = table.defaults.edge_size;
  for (const auto& [id, c] : table.per_material) edgeSize = std::min(edgeSize, c.edge_size);
  int nextCurve = 0;
  for (size_t i = 0; i < oracle.entries().size(); ++i) {
    const auto* solid = dynamic_cast<const BrepSolid*>(oracle.entries()[i].source.get());
    if (!solid) continue;
    FeatureGraph g = extractSharpEdges(*solid, static_cast<int>(i), job.sharp_angle_deg, edgeSize);
    for (FeaturePolyline& pl : g.polylines) {
      pl.curve = nextCurve++;  // extraction numbers per solid; the graph needs global ids
      all.polylines.push_back(std::move(pl));
    }
  }
  FeatureGraph clipped = clipToCompositeBoundary(all, oracle);
  // Where two inputs' boundaries cross (pin leaving the plate, cut faces across the plate).
  std::shared_ptr<const JunctionCurves> junctions;
  if (job.junctions) {
    junctions = std::make_shared<const JunctionCurves>(JunctionCurves::compute(oracle, job.sharp_angle_deg, &control));
    clipped = joinJunctions(clipped, junctions->polylines(edgeSize), oracle, *junctions);
  }
  clipped = removeCoincidentFeatures(clipped, oracle);
  for (const FeaturePolyline& pl : clipped.polylines)
    origins[pl.curve] = {pl.source, pl.edge, pl.junction, pl.junction >= 0 ? junctions : nullptr};
  return clipped;
}

uint64_t edgeKey(int64_t a, int64_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | static_cast<uint64_t>(b);
}

// Mesh_3 leaves boundary vertices within its bisection error of the surface. FreeCAD finds
// constraint nodes geometrically (1e-7 tolerance), so every boundary node is put exactly on
// the nearest B-rep face, and every feature node on its B-rep edge.
struct SnapResult {
  std::vector<int> vertex_entry;  // entry whose boundary the vertex was put on, -1 interior
  double max_move = 0;
  int64_t moved = 0;
};

BoundaryProjection projectOnCurve(const HierarchicalOracle& oracle, const CurveOrigin& origin, const Point3& p) {
  if (origin.junction >= 0 && origin.junctions) return origin.junctions->projectOnCurve(origin.junction, p);
  if (origin.entry < 0 || origin.edge < 0) return {};
  const auto* solid = dynamic_cast<const BrepSolid*>(oracle.entries()[origin.entry].source.get());
  if (!solid) return {};
  return solid->projectOnEdge(p, origin.edge);
}

SnapResult snapBoundaryVertices(TetMesh& mesh, const HierarchicalOracle& oracle,
                                const std::unordered_map<int, CurveOrigin>& origins, const RunControl& control) {
  SnapResult r;
  r.vertex_entry.assign(mesh.points.size(), -1);
  std::vector<char> onBoundary(mesh.points.size(), 0);
  for (const BoundaryTriangle& t : mesh.boundary)
    for (int64_t v : t.v) onBoundary[v] = 1;
  for (size_t v = 0; v < mesh.points.size(); ++v) {
    if (!onBoundary[v] && mesh.vertex_dimension[v] == 3) continue;
    if ((v & 1023) == 0) control.checkpoint();
    Point3& p = mesh.points[v];
    BoundaryProjection q;
    int entry = -1;
    const int curve = mesh.vertex_curve[v];
    if (mesh.vertex_dimension[v] <= 1 && curve >= 0 && origins.count(curve)) {
      const CurveOrigin& origin = origins.at(curve);
      q = projectOnCurve(oracle, origin, p);
      entry = origin.entry;
    }
    if (!std::isfinite(q.distance)) q = oracle.projectOnBoundary(p, &entry);
    r.vertex_entry[v] = entry;
    if (mesh.vertex_dimension[v] == 0) continue;  // corners are exact curve ends already
    if (mesh.vertex_dimension[v] == 3) mesh.vertex_dimension[v] = 2;
    if (!std::isfinite(q.distance)) continue;
    r.max_move = std::max(r.max_move, q.distance);
    if (q.distance > 0) ++r.moved;
    p = q.point;
  }
  return r;
}

json qualityJson(const QualityReport& q) {
  json j;
  j["min_dihedral_deg"] = q.min_dihedral;
  j["max_dihedral_deg"] = q.max_dihedral;
  j["max_radius_edge_ratio"] = q.max_radius_edge;
  j["mean_radius_edge_ratio"] = q.mean_radius_edge;
  j["min_dihedral_histogram_10deg"] = q.min_dihedral_histogram;
  j["inverted_tets"] = q.inverted;
  return j;
}

json criteriaJson(const MaterialCriteria& c) {
  return {{"cell_size", c.cell_size},   {"cell_radius_edge_ratio", c.cell_radius_edge_ratio},
          {"facet_size", c.facet_size}, {"facet_distance", c.facet_distance},
          {"facet_angle", c.facet_angle}, {"edge_size", c.edge_size}};
}

}  // namespace

JobResult runJob(const JobSpec& job, const RunControl& control) {
  PhaseClock clock;
  json report;
  report["engine"] = job.engine;
  report["version"] = version();
  json warnings = json::array();

  control.report("load", 0);
  std::vector<OracleEntry> entries;
  for (size_t i = 0; i < job.inputs.size(); ++i) {
    for (OracleEntry& entry : loadEntries(job.inputs[i])) entries.push_back(std::move(entry));
    control.report("load", double(i + 1) / job.inputs.size());
    control.checkpoint();
  }
  const HierarchicalOracle oracle(std::move(entries));
  const double diagonal = oracle.diagonal();
  if (diagonal > 1e5)
    warnings.push_back("the model is over 100 m across (" + std::to_string(diagonal) +
                       " model units): FreeCAD works in mm, check the units of the inputs");
  const CriteriaTable criteria = resolveCriteria(job, diagonal);
  checkExpectedSize(job, oracle.entries(), criteria);
  clock.finish("load");

  control.report("features", 0);
  std::unordered_map<int, CurveOrigin> origins;
  const FeatureGraph features = buildFeatures(job, oracle, criteria, control, origins);
  clock.finish("features");
  control.checkpoint();

  Mesh3Options options;
  options.criteria = criteria;
  options.perturb = job.perturb;
  options.exude = job.exude;
  options.optimize_time_limit = job.optimize_time_limit;
  options.sliver_bound = job.sliver_bound;
  options.max_vertices = job.max_vertices;
  options.seed = job.seed;
  Mesh3Statistics stats;
  JobResult result;
  result.mesh = meshWithCgalMesh3(oracle, features, options, control, &stats);
  clock.finish("mesh3");  // the engine's total; its phases are reported beside it
  for (const auto& [phase, s] : stats.seconds) clock.seconds["mesh3_" + phase] = s;
  TetMesh& mesh = result.mesh;

  control.report("snap", 0);
  mesh.boundary = extractBoundary(mesh);
  const SnapResult snap = snapBoundaryVertices(mesh, oracle, origins, control);
  clock.finish("snap");

  int64_t straightMidNodes = 0;
  if (job.element_order == 2) {
    control.report("second order", 0);
    std::unordered_map<uint64_t, int> featureCurveOfEdge;
    for (size_t i = 0; i < mesh.feature_edges.size(); ++i)
      featureCurveOfEdge[edgeKey(mesh.feature_edges[i][0], mesh.feature_edges[i][1])] = mesh.feature_edge_curves[i];
    std::set<uint64_t> boundaryEdges;
    for (const BoundaryTriangle& t : mesh.boundary)
      for (int k = 0; k < 3; ++k) boundaryEdges.insert(edgeKey(t.v[k], t.v[(k + 1) % 3]));
    // Mid nodes of curved edges and faces go onto the exact CAD geometry, the rest stay straight.
    auto place = [&](int64_t a, int64_t b, const Point3& mid) -> Point3 {
      const uint64_t key = edgeKey(a, b);
      auto f = featureCurveOfEdge.find(key);
      if (f != featureCurveOfEdge.end() && origins.count(f->second)) {
        const BoundaryProjection q = projectOnCurve(oracle, origins.at(f->second), mid);
        if (std::isfinite(q.distance)) return q.point;
      }
      if (!boundaryEdges.count(key)) return mid;
      const int ea = snap.vertex_entry[a], eb = snap.vertex_entry[b];
      const BoundaryProjection q = (ea >= 0 && ea == eb) ? oracle.entries()[ea].source->project(mid)
                                                          : oracle.projectOnBoundary(mid);
      return std::isfinite(q.distance) ? q.point : mid;
    };
    straightMidNodes = makeSecondOrder(mesh, place);
    clock.finish("second_order");
  }

  const QualityReport quality = measureQuality(mesh);
  const ConformityReport conformity = checkConformity(mesh);
  if (conformity.inverted_tets > 0)
    warnings.push_back(std::to_string(conformity.inverted_tets) +
                       " tetrahedra are inverted (or fold, for tet10) after putting nodes on the CAD faces");
  if (!conformity.ok()) warnings.push_back("the mesh failed its conformity check (see report.conformity)");

  json counts;
  counts["vertices"] = mesh.points.size();
  counts["tets"] = mesh.tets.size();
  counts["boundary_triangles"] = mesh.boundary.size();
  counts["feature_edges"] = mesh.feature_edges.size();
  json perMaterial = json::object();
  for (const auto& [material, n] : quality.tets_per_material) perMaterial[std::to_string(material)] = n;
  counts["tets_per_material"] = perMaterial;
  report["counts"] = counts;
  json volumes = json::object();
  for (const auto& [material, v] : quality.volume_per_material) volumes[std::to_string(material)] = v;
  report["volume_per_material"] = volumes;
  report["quality"] = qualityJson(quality);
  report["conformity"] = {{"faces_shared_by_more_than_two", conformity.faces_shared_by_more_than_two},
                          {"open_boundary_edges", conformity.open_boundary_edges},
                          {"inverted_tets", conformity.inverted_tets},
                          {"unused_points", conformity.unused_points},
                          {"inconsistent_mid_nodes", conformity.inconsistent_mid_nodes},
                          {"ok", conformity.ok()}};
  json crit = {{"default", criteriaJson(criteria.defaults)}, {"materials", json::object()}};
  for (const auto& [material, c] : criteria.per_material) crit["materials"][std::to_string(material)] = criteriaJson(c);
  crit["cell_radius_edge_ratio_applied"] = stats.radius_edge_ratio_used;
  crit["facet_angle_applied"] = stats.facet_angle_used;
  report["criteria"] = crit;
  report["features"] = {{"enabled", job.features},
                        {"sharp_angle_deg", job.sharp_angle_deg},
                        {"junctions", job.junctions},
                        {"polylines", features.polylines.size()},
                        {"protecting_ball_vertices", stats.protecting_balls}};
  report["seeds_on_boundary"] = stats.initial_points;
  report["boundary_snap"] = {{"max_move", snap.max_move},
                             {"max_move_relative", diagonal > 0 ? snap.max_move / diagonal : 0},
                             {"vertices_moved", snap.moved}};
  report["element_order"] = job.element_order;
  if (job.element_order == 2) report["second_order_straight_fallbacks"] = straightMidNodes;
  report["bbox_diagonal"] = diagonal;
  json materials = json::array();
  for (const OracleEntry& e : oracle.entries())
    materials.push_back({{"name", e.source->name()},
                         {"role", e.role == Role::Cut ? "cut" : "material"},
                         {"material", e.material},
                         {"source_volume", e.source->volume()}});
  report["inputs"] = materials;

  control.report("write", 0);
  for (const std::string& path : job.output_files) writeMeshFile(path, mesh);
  clock.finish("write");
  report["warnings"] = warnings;
  report["seconds"] = clock.seconds;
  if (!job.report_file.empty()) {
    std::ofstream out(job.report_file);
    if (!out) throw Error("cannot write the report to '" + job.report_file + "': check that the folder exists and is writable");
    out << report.dump(2) << "\n";
  }
  control.report("done", 1);
  result.report = std::move(report);
  return result;
}

}  // namespace oraclemesh
