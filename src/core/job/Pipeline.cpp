#include "job/Pipeline.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "Error.h"
#include "cgal/Mesh3Engine.h"
#include "domain/BrepSolid.h"
#include "domain/LabeledImage.h"
#include "domain/NrrdReader.h"
#include "domain/Sphere.h"
#include "domain/TriangleSurface.h"
#include "features/BrepSharpEdges.h"
#include "features/CoincidentFeatures.h"
#include "features/InputAngles.h"
#include "features/CurveSampling.h"
#include "features/FeatureSeparation.h"
#include "features/JunctionCurves.h"
#include "features/RuleSetQ.h"
#include "features/UserPolylines.h"
#include "mesh/Quality.h"
#include "mesh/SecondOrder.h"
#include "mesh/Topology.h"
#include "mesh/Writers.h"
#include "refine/ThesisEngine.h"

#include <TopExp_Explorer.hxx>

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

// One job input as oracle entries (a B-rep file with several solids gives one entry per
// solid), with what kind of input each entry is and the warnings of loading it.
struct LoadedInput {
  std::vector<OracleEntry> entries;
  std::vector<std::string> kinds;  // per entry: "B-rep solid", "triangle surface", ...
  std::vector<std::string> warnings;
};

LoadedInput loadInput(const InputSpec& in) {
  LoadedInput loaded;
  auto add = [&](SourcePtr source, int material, const std::string& kind) {
    loaded.entries.push_back({std::move(source), in.role, material});
    loaded.kinds.push_back(kind);
  };
  const bool surfaceFile = in.kind == InputSpec::Kind::File && [&] {
    std::string ext = std::filesystem::path(in.file).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext == ".stl" || ext == ".obj" || ext == ".off";
  }();
  if (in.kind == InputSpec::Kind::Image) {
    // One entry per mapped label. The regions of one image are disjoint, so their order among
    // themselves does not matter; together they take the image's place in the priority list.
    const auto image = readNrrdLabels(in.image, in.name);
    for (auto& [region, material] : makeImageRegions(image, in.image_materials, in.name))
      add(region, material, "image region");
  } else if (in.kind == InputSpec::Kind::Sphere) {
    add(std::make_shared<Sphere>(in.center, in.radius, in.name), in.material, "sphere");
  } else if (in.kind == InputSpec::Kind::Surface) {
    add(TriangleSurface::fromTriangles(in.surface_points, in.surface_triangles, in.name), in.material,
        "triangle surface");
  } else if (surfaceFile) {
    add(TriangleSurface::fromFile(in.file, in.name), in.material, "triangle surface");
  } else {
    const auto grouping = in.solids_together ? BrepSolid::Grouping::Together : BrepSolid::Grouping::Separate;
    BrepSolid::Loaded brep = in.kind == InputSpec::Kind::File ? BrepSolid::loadFile(in.file, in.name, grouping)
                                                               : BrepSolid::loadBrepText(in.brep_text, in.name, grouping);
    if (!in.solid_materials.empty() && in.solid_materials.size() != brep.solids.size())
      throw InputError("input '" + in.name + "'" + (in.file.empty() ? "" : " (file '" + in.file + "')") + " has " +
                       std::to_string(brep.solids.size()) + " solid" + (brep.solids.size() == 1 ? "" : "s") +
                       " but 'materials' lists " + std::to_string(in.solid_materials.size()) +
                       ": give one material per solid, in file order");
    for (size_t i = 0; i < brep.solids.size(); ++i) {
      int solids = 0;
      for (TopExp_Explorer ex(brep.solids[i]->shape(), TopAbs_SOLID); ex.More(); ex.Next()) ++solids;
      add(brep.solids[i], in.solid_materials.empty() ? in.material : in.solid_materials[i],
          solids == 1 ? "B-rep solid" : "B-rep compound (" + std::to_string(solids) + " solids)");
    }
    loaded.warnings = std::move(brep.warnings);
  }
  return loaded;
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
  const std::vector<Point3>* user = nullptr;        // the job's polyline for a user polyline
  std::shared_ptr<const UserCurve> user_curve;      // its exact CAD edge, when the job gave one
};

// The CGAL Mesh_3 settings of a job: the Mesh_3 engine's, and the sliver removal every
// engine's mesh goes through.
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

// Mesh_3's protecting balls along the features: the job's edge size, lowered where curves run
// close to one another or are short (features/FeatureSeparation), down to 1e-4 of the diagonal.
FeatureEdgeSizes localEdgeSizes(const FeatureGraph& features, const CriteriaTable& table, double diagonal) {
  return localFeatureEdgeSizes(features, table.strictest(&MaterialCriteria::edge_size), 1e-4 * diagonal,
                               1e-9 * diagonal);
}

json localEdgeSizesJson(const FeatureEdgeSizes& sizes) {
  json j = {{"smallest", sizes.smallest}, {"points_lowered", sizes.bounded_points}};
  if (std::isfinite(sizes.closest_separation)) {
    j["closest_curves_apart"] = sizes.closest_separation;
    j["closest_curves_at"] = sizes.closest_at;
  }
  return j;
}

// What the Rule Set Q preparation did, for the report.
struct FeaturePreparation {
  int64_t crossing_pieces = 0;  // polylines added by splitting at crossings
  int64_t star_vertices = 0;
  std::shared_ptr<const JunctionCurves> junctions;  // null when junctions are off
};

// The chord bound of the feature polylines: 0 (the default, featureSagittaTolerance) except
// for the thesis engine, whose polyline samples are all mesh vertices (thesisSagittaTolerance).
double thesisEngineSagitta(const JobSpec& job, const CriteriaTable& table, double edgeSize) {
  if (job.engine != "thesis") return 0;
  return thesisSagittaTolerance(edgeSize, table.strictest(&MaterialCriteria::facet_distance));
}

FeatureGraph buildFeatures(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& table,
                           const RunControl& control, std::unordered_map<int, CurveOrigin>& origins,
                           FeaturePreparation& preparation) {
  FeatureGraph all;
  if (!job.features) return all;
  const double edgeSize = table.strictest(&MaterialCriteria::edge_size);
  const double sagitta = thesisEngineSagitta(job, table, edgeSize);
  int nextCurve = 0;
  for (size_t i = 0; i < oracle.entries().size() && job.sharp_angle_deg > 0; ++i) {
    const auto* solid = oracle.entries()[i].source->brepTopology();
    if (!solid) continue;
    FeatureGraph g = extractSharpEdges(*solid, static_cast<int>(i), job.sharp_angle_deg, edgeSize, sagitta);
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
    clipped = joinJunctions(clipped, junctions->polylines(edgeSize, sagitta), oracle, *junctions);
  }
  preparation.junctions = junctions;
  // Parts in contact along an arc sample it twice, a sagitta apart: those copies are one curve.
  clipped = removeCoincidentFeatures(clipped, oracle, 2 * featureSagittaTolerance(edgeSize, oracle.diagonal()));
  std::vector<std::shared_ptr<const UserCurve>> userCurves(job.user_polylines.size());
  for (size_t i = 0; i < job.user_polyline_curves.size() && i < userCurves.size(); ++i)
    if (!job.user_polyline_curves[i].empty())
      userCurves[i] = UserCurve::fromBrep(job.user_polyline_curves[i], "features.polylines[" + std::to_string(i) + "].brep");
  if (!job.user_polylines.empty()) {
    const FeatureGraph user = userPolylineFeatures(job.user_polylines, oracle, edgeSize, userCurves);
    clipped.polylines.insert(clipped.polylines.end(), user.polylines.begin(), user.polylines.end());
  }
  // Rule Set Q (thesis §3.2.2). Sharp edges of different inputs can cross mid-segment (edges
  // of two parts on a common plane), so every graph is split, not only one with user curves.
  // User curves snap onto CAD chords within 2.5 % of the edge size (chords of curved CAD edges
  // are up to 2 % off the curve); two CAD curves cross where their chords come within twice
  // the sampling sagitta, but not within an edge size of an end they share (part.step has
  // curves leaving a vertex at under a degree).
  const size_t unsplit = clipped.polylines.size();
  const double crossingSagitta = sagitta > 0 ? sagitta : featureSagittaTolerance(edgeSize, oracle.diagonal());
  clipped = splitAtCrossings(clipped, 0.025 * edgeSize, 2 * crossingSagitta, edgeSize);
  preparation.crossing_pieces = static_cast<int64_t>(clipped.polylines.size() - unsplit);
  // Ends are shared bitwise by construction; the tolerance only absorbs rounding.
  const std::vector<StarVertex> stars = findStarVertices(clipped, 1e-9 * oracle.diagonal());
  preparation.star_vertices = static_cast<int64_t>(stars.size());
  // The thesis engine applies Q1 itself (T1.1, with l_min,i of these polylines); equalising
  // here as well would make it split the already equalised segments again, at l_min,i / 9.
  if (job.engine != "thesis") clipped = equalizeStarSegments(clipped, stars);
  for (const FeaturePolyline& pl : clipped.polylines)
    origins[pl.curve] = {pl.source, pl.edge, pl.junction, pl.junction >= 0 ? junctions : nullptr,
                         pl.user >= 0 ? &job.user_polylines[pl.user] : nullptr,
                         pl.user >= 0 ? userCurves[pl.user] : nullptr};
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
  // Vertices left where Mesh_3 put them because the move would have flattened or inverted a
  // tet that could not be removed (interface slivers, where curves meet at small angles).
  int64_t kept_off_surface = 0;
  int64_t slivers_removed = 0;  // flat tets on the outer surface (see removeFlatSurfaceSlivers)
  // Surface vertices the engine put exactly on a known entry's boundary (mesh.vertex_boundary_entry),
  // taken as they are instead of projected again.
  int64_t on_boundary_by_engine = 0;
  double max_distance_kept = 0;
  Point3 worst_kept{};
};

BoundaryProjection projectOnCurve(const HierarchicalOracle& oracle, const CurveOrigin& origin, const Point3& p) {
  if (origin.junction >= 0 && origin.junctions) return origin.junctions->projectOnCurve(origin.junction, p);
  if (origin.user) {
    const Point3 q = origin.user_curve ? origin.user_curve->nearest(p) : nearestOnPolyline(*origin.user, p);
    return {q, -1, distance(p, q)};
  }
  if (origin.entry < 0 || origin.edge < 0) return {};
  const auto* solid = oracle.entries()[origin.entry].source->brepTopology();
  if (!solid) return {};
  return solid->projectOnEdge(p, origin.edge);
}

// Feature edges of `mesh` that are not edges of any of its tets (0 when every constrained
// subsegment is a mesh edge).
int64_t featureEdgesMissingFromTets(const TetMesh& mesh) {
  std::unordered_set<uint64_t> tetEdges;
  tetEdges.reserve(mesh.tets.size() * 7);
  for (const auto& t : mesh.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) tetEdges.insert(edgeKey(t[a], t[b]));
  int64_t missing = 0;
  for (const auto& e : mesh.feature_edges) missing += tetEdges.count(edgeKey(e[0], e[1])) == 0;
  return missing;
}

// Whether moving vertex v to `target` would turn one of its (positively oriented) tets flat or
// inside out.
bool degeneratesAnIncidentTet(const TetMesh& mesh, const std::vector<int64_t>& tets, int64_t v, const Point3& target) {
  for (int64_t t : tets) {
    std::array<Point3, 4> corners;
    for (int k = 0; k < 4; ++k) corners[k] = mesh.tets[t][k] == v ? target : mesh.points[mesh.tets[t][k]];
    if (tetVolume(corners[0], corners[1], corners[2], corners[3]) <= 0) return true;
  }
  return false;
}

std::vector<std::vector<int64_t>> tetsOfVertices(const TetMesh& mesh) {
  std::vector<std::vector<int64_t>> tets(mesh.points.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) tets[mesh.tets[t][k]].push_back(static_cast<int64_t>(t));
  return tets;
}

// Mesh_3 leaves slivers lying on the outer surface (four corners on one face, or across a
// sharp edge) that go flat or inside out once their corners are on the CAD faces. Such a tet
// with two or three faces on the outside holds no volume of the part: removing it leaves its
// other faces as the (equally flat) surface there. Interface slivers are not removed (that
// would open the interface); the snap leaves their corners where they are instead.
int64_t removeFlatSurfaceSlivers(TetMesh& mesh, const std::vector<Point3>& target) {
  // The outer faces are the boundary triangles with nothing beyond them (mesh.boundary is
  // current when the snap runs).
  std::set<std::array<int64_t, 3>> outer;
  for (const BoundaryTriangle& b : mesh.boundary)
    if (b.material_out == 0) {
      std::array<int64_t, 3> f = b.v;
      std::sort(f.begin(), f.end());
      outer.insert(f);
    }
  auto faceOf = [&](size_t t, int skip) {
    std::array<int64_t, 3> f{};
    int n = 0;
    for (int k = 0; k < 4; ++k)
      if (k != skip) f[n++] = mesh.tets[t][k];
    std::sort(f.begin(), f.end());
    return f;
  };
  std::set<std::array<int64_t, 3>> exposed;  // inner faces of tets removed in this pass
  std::vector<char> remove(mesh.tets.size(), 0);
  int64_t removed = 0;
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    int outside = 0;
    bool nextToRemoved = false;
    for (int k = 0; k < 4; ++k) {
      const auto f = faceOf(t, k);
      outside += outer.count(f) > 0;
      nextToRemoved |= exposed.count(f) > 0;
    }
    // A neighbour of a removed tet waits for another pass: removing both sides of a face
    // would open the mesh.
    if (outside < 2 || outside > 3 || nextToRemoved) continue;
    const auto& c = mesh.tets[t];
    if (tetVolume(target[c[0]], target[c[1]], target[c[2]], target[c[3]]) > 0) continue;
    remove[t] = 1;
    ++removed;
    for (int k = 0; k < 4; ++k)
      if (!outer.count(faceOf(t, k))) exposed.insert(faceOf(t, k));
  }
  if (removed == 0) return 0;
  size_t kept = 0;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    if (!remove[t]) {
      mesh.tets[kept] = mesh.tets[t];
      mesh.tet_materials[kept] = mesh.tet_materials[t];
      ++kept;
    }
  mesh.tets.resize(kept);
  mesh.tet_materials.resize(kept);
  mesh.boundary = extractBoundary(mesh);
  return removed;
}

SnapResult snapBoundaryVertices(TetMesh& mesh, const HierarchicalOracle& oracle,
                                const std::unordered_map<int, CurveOrigin>& origins, const RunControl& control) {
  SnapResult r;
  r.vertex_entry.assign(mesh.points.size(), -1);
  std::vector<char> onBoundary(mesh.points.size(), 0);
  for (const BoundaryTriangle& t : mesh.boundary)
    for (int64_t v : t.v) onBoundary[v] = 1;
  // Where each boundary or feature vertex belongs: on its feature curve, else on the nearest
  // CAD face. Corners are exact curve ends already.
  std::vector<Point3> target = mesh.points;
  std::vector<double> move(mesh.points.size(), 0.0);
  for (size_t v = 0; v < mesh.points.size(); ++v) {
    if (!onBoundary[v] && mesh.vertex_dimension[v] == 3) continue;
    if ((v & 1023) == 0) control.checkpoint();
    // The thesis engine's surface vertices are oracle crossings or projections already: a
    // projection would only find them where they are (implant_in_bone (a): 1,991 vertices
    // moved by at most 2e-13 mm, at 12 % of the job's time).
    if (mesh.vertex_dimension[v] == 2 && !mesh.vertex_boundary_entry.empty() && mesh.vertex_boundary_entry[v] >= 0) {
      r.vertex_entry[v] = mesh.vertex_boundary_entry[v];
      ++r.on_boundary_by_engine;
      continue;
    }
    BoundaryProjection q;
    int entry = -1;
    const int curve = mesh.vertex_curve[v];
    if (mesh.vertex_dimension[v] <= 1 && curve >= 0 && origins.count(curve)) {
      const CurveOrigin& origin = origins.at(curve);
      q = projectOnCurve(oracle, origin, mesh.points[v]);
      entry = origin.entry;
    }
    if (!std::isfinite(q.distance)) q = oracle.projectOnBoundary(mesh.points[v], &entry);
    r.vertex_entry[v] = entry;
    if (mesh.vertex_dimension[v] == 0) continue;
    if (mesh.vertex_dimension[v] == 3) mesh.vertex_dimension[v] = 2;
    if (!std::isfinite(q.distance) || q.distance == 0) continue;
    target[v] = q.point;
    move[v] = q.distance;
  }
  r.slivers_removed = removeFlatSurfaceSlivers(mesh, target);
  const std::vector<std::vector<int64_t>> tetsOfVertex = tetsOfVertices(mesh);
  // A move that would fold a tet now may be fine once the tet's other corners have moved
  // (neighbouring nodes on two curves meeting at a small angle): passes over the nodes still
  // off their target repeat, in index order, until one moves none.
  std::vector<int64_t> pending;
  for (size_t v = 0; v < mesh.points.size(); ++v)
    if (move[v] != 0) pending.push_back(static_cast<int64_t>(v));
  for (size_t before = pending.size() + 1; !pending.empty() && pending.size() < before;) {
    before = pending.size();
    std::vector<int64_t> blocked;
    for (int64_t v : pending) {
      if (degeneratesAnIncidentTet(mesh, tetsOfVertex[v], v, target[v])) {
        blocked.push_back(v);
        continue;
      }
      r.max_move = std::max(r.max_move, move[v]);
      ++r.moved;
      mesh.points[v] = target[v];
    }
    pending.swap(blocked);
  }
  for (int64_t v : pending) {
    ++r.kept_off_surface;
    if (move[v] > r.max_distance_kept) {
      r.max_distance_kept = move[v];
      r.worst_kept = mesh.points[v];
    }
  }
  return r;
}

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

// report.thesis.planar_faces: what the planar-face layer recovered and what it left.
json planarFacesJson(const PlanarFaceStatistics& stats, const std::vector<SkippedPlanarFace>& skipped,
                     const HierarchicalOracle& oracle) {
  json missing = json::array();
  for (const MissingPlanarTriangle& t : stats.missing_triangles)
    missing.push_back({{"input", oracle.entries()[t.entry].source->name()}, {"face", t.face},
                       {"circumcentre", t.circumcentre}, {"circumradius", t.radius}, {"reason", t.reason}});
  json left = json::array();
  for (const SkippedPlanarFace& f : skipped)
    left.push_back({{"input", oracle.entries()[f.entry].source->name()}, {"face", f.face}, {"reason", f.reason}});
  return {{"faces", stats.faces},
          {"triangles", stats.triangles},
          {"missing_at_first_check", stats.missing_at_first_check},
          {"insertions", stats.insertions},
          {"missing", stats.missing},
          {"missing_triangles", missing},
          {"skipped_faces", left}};
}

json criteriaJson(const MaterialCriteria& c) {
  return {{"cell_size", c.cell_size},   {"cell_radius_edge_ratio", c.cell_radius_edge_ratio},
          {"facet_size", c.facet_size}, {"facet_distance", c.facet_distance},
          {"facet_angle", c.facet_angle}, {"edge_size", c.edge_size}};
}

// The dihedral angle the thesis engine's sliver removal (rule S, then perturbation) aims for:
// 5 degrees above optimize.sliver_bound. The perturber stops as soon as every tet clears its
// bound, and slight moves after it (vertices it left off the faces going back in the snap)
// may cost a little; with the margin the final mesh clears the job's bound (default 10: demo
// assembly and implant_in_bone 15 degrees). Rule S aims as high as perturbation: below it,
// the perturber spends seconds on lifting what rule S left (demo: 20 s instead of 0.3 s).
double thesisSliverBound(const JobSpec& job) {
  constexpr double kMarginDeg = 5, kMaxDeg = 69;  // below the regular tetrahedron's 70.5
  return std::min(job.sliver_bound + kMarginDeg, kMaxDeg);
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
  std::vector<std::string> entryKinds, entryInputs;
  for (size_t i = 0; i < job.inputs.size(); ++i) {
    const InputSpec& in = job.inputs[i];
    LoadedInput loaded = loadInput(in);
    for (size_t k = 0; k < loaded.entries.size(); ++k) {
      entries.push_back(std::move(loaded.entries[k]));
      entryKinds.push_back(loaded.kinds[k]);
      entryInputs.push_back(in.name);
    }
    for (std::string& w : loaded.warnings) warnings.push_back(std::move(w));
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
  FeaturePreparation preparation;
  const FeatureGraph features = buildFeatures(job, oracle, criteria, control, origins, preparation);
  // 60 degrees: the thesis' termination bound for Rule Set T (§3.3).
  constexpr double kSmallAngleLimitDeg = 60;
  const std::vector<SmallInputAngle> smallAngles = findSmallInputAngles(oracle, features, kSmallAngleLimitDeg, preparation.junctions.get());
  if (!smallAngles.empty()) {
    const SmallInputAngle& worst = smallAngles.front();
    std::ostringstream message;
    message << smallAngles.size() << " input angle(s) under " << kSmallAngleLimitDeg << " degrees; the smallest is "
            << worst.angle_deg << " degrees (" << worst.kind << ") of input '" << worst.input << "' at ("
            << worst.location[0] << ", " << worst.location[1] << ", " << worst.location[2]
            << "): elements there can stay poor; see report.small_input_angles";
    warnings.push_back(message.str());
  }
  clock.finish("features");
  control.checkpoint();

  JobResult result;
  json engineReport;
  int64_t seedsOnBoundary = 0, protectingBalls = 0;
  if (job.engine == "thesis") {
    RuleSetTOptions options;
    options.criteria = criteria;
    options.assignment =
        job.material_assignment == "barycenter" ? MaterialAssignment::Barycenter : MaterialAssignment::Circumcenter;
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
      for (const FeaturePolyline& pl : features.polylines)
        if (pl.edge == a.edge && pl.source >= 0 && oracle.entries()[pl.source].source->name() == a.input)
          options.small_angle_curves.push_back(pl.curve);
    }
    // Sliver removal (optimize.perturb) starts in the engine: rule S, after T1-T3, lifts the
    // slivers perturbation cannot (next to segment vertices, which it keeps fixed: on the demo
    // assembly perturbation alone stops at 3.6 degrees).
    options.sliver_dihedral_deg = job.perturb ? thesisSliverBound(job) : 0;
    // Segment vertices go onto the curves, so the snap leaves them where they are (moving them
    // by the chord's sagitta took implant_in_bone (a) from 13.7 degrees before the snap to 7.9
    // after it).
    options.onto_curve = [&](int curve, const Point3& p) {
      auto origin = origins.find(curve);
      const BoundaryProjection q =
          origin == origins.end() ? BoundaryProjection{} : projectOnCurve(oracle, origin->second, p);
      return std::isfinite(q.distance) ? q.point : p;
    };
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
    const bool slivers_left = stats.insertions.count("left_slivers") && stats.insertions.at("left_slivers") > 0;
    if (job.perturb && slivers_left) {
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
      const int64_t dropped = featureEdgesMissingFromTets(result.mesh) +
                              std::max<int64_t>(0, static_cast<int64_t>(beforePerturbation.feature_edges.size()) -
                                                       static_cast<int64_t>(result.mesh.feature_edges.size()));
      if (dropped > 0) {
        result.mesh = std::move(beforePerturbation);
        warnings.push_back("CGAL's sliver perturbation took " + std::to_string(dropped) +
                           " constrained subsegment(s) out of the mesh, so the mesh before it is kept (slivers rule S "
                           "and P left stay: see report.thesis.slivers_left)");
      }
      clock.finish("sliver_removal");
    }
    seedsOnBoundary = stats.initial_points;
    json left = json::array();
    for (const LeftElement& e : stats.left)
      left.push_back({{"kind", e.kind}, {"reason", e.reason}, {"location", e.location}, {"material", e.material},
                      {"value", e.value}});
    json slivers = json::array();
    for (const LeftElement& e : stats.slivers_left)
      slivers.push_back({{"reason", e.reason}, {"location", e.location}, {"material", e.material},
                         {"min_dihedral_deg", e.value}});
    engineReport = {{"rule_insertions", stats.insertions},
                    {"star_vertices", stats.star_vertices},
                    {"constrained_subsegments", stats.constrained_subsegments},
                    {"final_check",
                     {{"subsegments_not_edges", stats.subsegments_not_edges},
                      {"encroached_subsegments", stats.encroached_subsegments},
                      {"restricted_facets_off_boundary", stats.restricted_facets_off_boundary}}},
                    {"elements_left", left},
                    {"slivers_left", slivers}};
    if (job.planar_faces) {
      engineReport["planar_faces"] = planarFacesJson(stats.planar, skippedPlanarFaces, oracle);
      if (stats.planar.missing > 0)
        warnings.push_back(std::to_string(stats.planar.missing) +
                           " triangle(s) of planar faces are not mesh facets (see report.thesis.planar_faces)");
    }
    if (!stats.left.empty())
      warnings.push_back(std::to_string(stats.insertions["left_elements"]) +
                         " element(s) still violate their criteria (see report.thesis.elements_left for where and "
                         "why; small input angles are the usual cause)");
  } else {
    Mesh3Options options = mesh3Options(job, criteria);
    const FeatureEdgeSizes edgeSizes = localEdgeSizes(features, criteria, diagonal);
    options.feature_edge_sizes = edgeSizes.at_points;
    Mesh3Statistics stats;
    result.mesh = meshWithCgalMesh3(oracle, features, options, control, &stats);
    clock.finish("mesh3");  // the engine's total; its phases are reported beside it
    for (const auto& [phase, sec] : stats.seconds) clock.seconds["mesh3_" + phase] = sec;
    seedsOnBoundary = stats.initial_points;
    protectingBalls = stats.protecting_balls;
    engineReport = {{"cell_radius_edge_ratio_applied", stats.radius_edge_ratio_used},
                    {"facet_angle_applied", stats.facet_angle_used},
                    {"feature_edge_size", localEdgeSizesJson(edgeSizes)}};
  }
  TetMesh& mesh = result.mesh;

  control.report("snap", 0);
  mesh.boundary = extractBoundary(mesh);
  // What the snap costs in quality (each engine leaves some boundary vertices off the faces).
  const double minDihedralBeforeSnap = measureQuality(mesh).min_dihedral;
  const SnapResult snap = snapBoundaryVertices(mesh, oracle, origins, control);
  clock.finish("snap");
  if (snap.kept_off_surface > 0) {
    std::ostringstream message;
    message << snap.kept_off_surface << " boundary node(s) stay up to " << snap.max_distance_kept
            << " from the CAD faces (worst near (" << snap.worst_kept[0] << ", " << snap.worst_kept[1] << ", "
            << snap.worst_kept[2] << ")): putting them on the faces would flatten or invert elements; FEM constraints "
               "on those faces may miss them (a finer edge_size near small input angles helps)";
    warnings.push_back(message.str());
  }

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
    straightMidNodes -= curveStraightFeatureMidNodes(mesh, [&](int64_t a, int64_t b, const Point3& p) -> Point3 {
      auto f = featureCurveOfEdge.find(edgeKey(a, b));
      const BoundaryProjection q = f != featureCurveOfEdge.end() && origins.count(f->second)
                                       ? projectOnCurve(oracle, origins.at(f->second), p)
                                       : BoundaryProjection{};
      return std::isfinite(q.distance) ? q.point : Point3{NAN, NAN, NAN};
    });
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
  if (job.engine == "cgal") {
    crit["cell_radius_edge_ratio_applied"] = engineReport["cell_radius_edge_ratio_applied"];
    crit["facet_angle_applied"] = engineReport["facet_angle_applied"];
    crit["feature_edge_size_applied"] = engineReport["feature_edge_size"];
  } else {
    report["thesis"] = engineReport;
    report["material_assignment"] = job.material_assignment;
  }
  report["criteria"] = crit;
  int64_t sharpPolylines = 0, junctionPolylines = 0, userPolylines = 0;
  for (const FeaturePolyline& pl : features.polylines) {
    sharpPolylines += pl.edge >= 0;
    junctionPolylines += pl.junction >= 0;
    userPolylines += pl.user >= 0;
  }
  report["features"] = {{"enabled", job.features},
                        {"sharp_edge_polylines", sharpPolylines},
                        {"junction_polylines", junctionPolylines},
                        {"user_polylines", userPolylines},
                        {"sharp_angle_deg", job.sharp_angle_deg},
                        {"junctions", job.junctions},
                        {"polylines", features.polylines.size()},
                        {"crossing_pieces", preparation.crossing_pieces},
                        {"star_vertices", preparation.star_vertices},
                        {"protecting_ball_vertices", protectingBalls}};
  json angles = json::array();
  for (const SmallInputAngle& a : smallAngles)
    angles.push_back({{"kind", a.kind}, {"angle_deg", a.angle_deg}, {"location", a.location},
                      {"input", a.input}, {"edge", a.edge}});
  report["small_input_angles"] = angles;
  report["small_input_angle_limit_deg"] = kSmallAngleLimitDeg;
  report["seeds_on_boundary"] = seedsOnBoundary;
  report["boundary_snap"] = {{"max_move", snap.max_move},
                             {"max_move_relative", diagonal > 0 ? snap.max_move / diagonal : 0},
                             {"vertices_moved", snap.moved},
                             {"vertices_on_boundary_by_engine", snap.on_boundary_by_engine},
                             {"vertices_kept_off_surface", snap.kept_off_surface},
                             {"flat_surface_slivers_removed", snap.slivers_removed},
                             {"max_distance_kept_off_surface", snap.max_distance_kept},
                             {"min_dihedral_before_deg", minDihedralBeforeSnap}};
  report["element_order"] = job.element_order;
  if (job.element_order == 2) report["second_order_straight_fallbacks"] = straightMidNodes;
  report["bbox_diagonal"] = diagonal;
  json materials = json::array();
  for (size_t i = 0; i < oracle.entries().size(); ++i) {
    const OracleEntry& e = oracle.entries()[i];
    materials.push_back({{"name", e.source->name()},
                         {"input", entryInputs[i]},
                         {"kind", entryKinds[i]},
                         {"role", e.role == Role::Cut ? "cut" : "material"},
                         {"material", e.material},
                         {"source_volume", e.source->volume()}});
  }
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
