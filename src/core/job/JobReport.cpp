#include "job/JobReport.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "Error.h"
#include "job/ResolvedCriteria.h"
#include "sizing/Fineness.h"

namespace oraclemesh {

namespace {

using nlohmann::json;

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

json localEdgeSizesJson(const FeatureEdgeSizes& sizes) {
  json j = {{"smallest", sizes.smallest}, {"points_lowered", sizes.bounded_points}};
  if (std::isfinite(sizes.closest_separation)) {
    j["closest_curves_apart"] = sizes.closest_separation;
    j["closest_curves_at"] = sizes.closest_at;
  }
  return j;
}

// report.thesis.planar_faces: what the planar-face layer recovered and what it left.
json planarFacesJson(const PlanarFaceStatistics& stats, const std::vector<SkippedPlanarFace>& skipped,
                     const std::vector<InputReport>& inputs) {
  json missing = json::array();
  for (const MissingPlanarTriangle& t : stats.missing_triangles)
    missing.push_back({{"input", inputs[t.entry].name}, {"face", t.face},
                       {"circumcentre", t.circumcentre}, {"circumradius", t.radius}, {"reason", t.reason}});
  json left = json::array();
  for (const SkippedPlanarFace& f : skipped)
    left.push_back({{"input", inputs[f.entry].name}, {"face", f.face}, {"reason", f.reason}});
  return {{"faces", stats.faces},
          {"triangles", stats.triangles},
          {"missing_at_first_check", stats.missing_at_first_check},
          {"insertions", stats.insertions},
          {"missing", stats.missing},
          {"missing_triangles", missing},
          {"skipped_faces", left}};
}

json thesisJson(const ThesisEngineReport& thesis, const std::vector<InputReport>& inputs) {
  const RuleSetTStatistics& stats = thesis.statistics;
  json left = json::array();
  for (const LeftElement& e : stats.left)
    left.push_back({{"kind", e.kind}, {"reason", e.reason}, {"location", e.location}, {"material", e.material},
                    {"value", e.value}});
  json slivers = json::array();
  for (const LeftElement& e : stats.slivers_left)
    slivers.push_back({{"reason", e.reason}, {"location", e.location}, {"material", e.material},
                       {"min_dihedral_deg", e.value}});
  json engineReport = {{"rule_insertions", stats.insertions},
                       {"vertex_moves", stats.vertex_moves},
                       {"encroachment_refusals", stats.encroachment_refusals},
                       {"star_vertices", stats.star_vertices},
                       {"constrained_subsegments", stats.constrained_subsegments},
                       {"final_check",
                        {{"subsegments_not_edges", stats.subsegments_not_edges},
                         {"subsegments_outside_material", stats.subsegments_outside_material},
                         {"subsegments_kept_by_barycentre", stats.subsegments_kept_by_barycentre},
                         {"cells_labelled_by_barycentre", stats.cells_labelled_by_barycentre},
                         {"encroached_subsegments", stats.encroached_subsegments},
                         {"restricted_facets_off_boundary", stats.restricted_facets_off_boundary}}},
                       {"elements_left", left},
                       {"elements_left_total", stats.elements_left_total},
                       {"slivers_left", slivers},
                       {"slivers_left_total", stats.slivers_left_total}};
  if (thesis.planar_faces)
    engineReport["planar_faces"] = planarFacesJson(stats.planar, thesis.skipped_planar_faces, inputs);
  return engineReport;
}

// A sizing field's figures: its grading and cap, its samples per reason, its smallest size.
json sizeFieldJson(const SizeField& field) {
  json samples = json::object();
  for (int r = 0; r < kSizeReasonCount; ++r)
    if (field.sampleCount(static_cast<SizeReason>(r)) > 0)
      samples[sizeReasonName(static_cast<SizeReason>(r))] = field.sampleCount(static_cast<SizeReason>(r));
  json j = {{"grading", field.grading()}, {"largest", field.cap()}, {"samples", samples},
            {"samples_taken", field.samplesTaken()}};
  if (field.sampleCount() > 0)
    j["smallest"] = {{"size", field.smallestSize()}, {"at", field.smallestAt()},
                     {"reason", sizeReasonName(field.smallestReason())}};
  return j;
}

json criteriaReportJson(const JobReport& r) {
  json crit = {{"default", criteriaJson(r.criteria.defaults)}, {"materials", json::object()}};
  for (const auto& [material, c] : r.criteria.per_material) crit["materials"][std::to_string(material)] = criteriaJson(c);
  crit["fineness"] = r.fineness;
  const FinenessPreset* preset = findFineness(r.fineness);
  // report.criteria.size_field: what the geometry asked for, where the job left sizes unset.
  if (r.criteria.field) {
    crit["size_field"] = sizeFieldJson(*r.criteria.field);
    crit["size_field"]["fineness"] = r.fineness;
    crit["size_field"]["segments_per_circle"] = preset->segments_per_circle;
    crit["size_field"]["sizes_per_thickness"] = preset->sizes_per_thickness;
    crit["size_field"]["cell_size_per_surface_size"] = kCellSizePerSurfaceSize;
  }
  // report.criteria.gap_sizes: the gaps between parts the sizes keep open, narrowest first (a
  // width at the CAD's tolerance is a pair the user may want bonded: contact_tolerance).
  json gaps = json::array();
  for (const PartGap& g : r.gaps)
    gaps.push_back({{"between", {r.inputs[g.entry].name, r.inputs[g.other].name}}, {"width", g.width}, {"at", g.at}});
  crit["gap_sizes"] = r.criteria.gap_field ? sizeFieldJson(*r.criteria.gap_field) : json::object();
  crit["gap_sizes"]["gaps"] = gaps;
  crit["gap_sizes"]["sizes_per_gap"] = kSizesPerGap;
  // report.criteria.gap_sizes.bonded_wedges: per pair of parts resting on each other
  // tangentially, the widest gap beside the contact the mesh bonds and where.
  std::map<std::pair<int, int>, const BondedWedgeSample*> widest;
  if (r.criteria.bonded_wedges)
    for (const BondedWedgeSample& s : r.criteria.bonded_wedges->samples()) {
      const BondedWedgeSample*& w = widest[{s.entry, s.other}];
      if (!w || s.width > w->width) w = &s;
    }
  json wedges = json::array();
  for (const auto& [pair, s] : widest)
    wedges.push_back({{"between", {r.inputs[pair.first].name, r.inputs[pair.second].name}},
                      {"widest", s->width}, {"at", s->at}});
  crit["gap_sizes"]["bonded_wedges"] = wedges;
  crit["gap_sizes"]["wedge_bond_per_size"] = kWedgeBondPerSize;
  if (r.engine_run.mesh3) {
    const Mesh3EngineReport& mesh3 = *r.engine_run.mesh3;
    crit["cell_radius_edge_ratio_applied"] = mesh3.statistics.radius_edge_ratio_used;
    crit["facet_angle_applied"] = mesh3.statistics.facet_angle_used;
    crit["feature_edge_size_applied"] = localEdgeSizesJson(mesh3.feature_edge_sizes);
  }
  return crit;
}

json countsJson(const MeshCounts& c, const QualityReport& quality) {
  json counts;
  counts["vertices"] = c.vertices;
  counts["tets"] = c.tets;
  counts["boundary_triangles"] = c.boundary_triangles;
  counts["feature_edges"] = c.feature_edges;
  json perMaterial = json::object();
  for (const auto& [material, n] : quality.tets_per_material) perMaterial[std::to_string(material)] = n;
  counts["tets_per_material"] = perMaterial;
  return counts;
}

json conformityJson(const ConformityReport& conformity) {
  return {{"faces_shared_by_more_than_two", conformity.faces_shared_by_more_than_two},
          {"open_boundary_edges", conformity.open_boundary_edges},
          {"inverted_tets", conformity.inverted_tets},
          {"unused_points", conformity.unused_points},
          {"inconsistent_mid_nodes", conformity.inconsistent_mid_nodes},
          {"ok", conformity.ok()}};
}

json selfCheckJson(const MeshSelfCheck& check, MeshCheckMode mode) {
  json materials = json::object();
  for (const auto& [m, c] : check.materials)
    materials[std::to_string(m)] = {{"parts", c.parts},
                                    {"input_volume", c.input_volume},
                                    {"input_volume_error_bar", c.error_bar},
                                    {"mesh_volume", c.mesh_volume},
                                    {"deviation", c.deviation},
                                    {"components", c.components},
                                    {"max_components", c.max_components}};
  json joined = json::array();
  for (const JoinedAcrossGap& j : check.joined)
    joined.push_back({{"materials", {j.material, j.other_material}},
                      {"interface_area", j.interface_area},
                      {"joined_area", j.joined_area},
                      {"widest_gap", j.widest_gap},
                      {"widest_at", j.widest_at}});
  return {{"mode", mode == MeshCheckMode::Error ? "error" : "warn"},
          {"volume_tolerance", check.volume_tolerance},
          {"materials", materials},
          {"contact_tolerance", check.contact_tolerance},
          {"joined", joined},
          {"problems", check.problems},
          {"ok", check.problems.empty()}};
}

json tangentCuspsJson(const std::vector<TangentCusp>& cusps) {
  json list = json::array();
  for (const TangentCusp& c : cusps)
    list.push_back({{"location", c.vertex},
                    {"input", c.input},
                    {"trimmed_edge", c.trimmed_edge},
                    {"kept_edge", c.kept_edge},
                    {"parting_point", c.parting_point},
                    {"resumes_at", c.resumes_at},
                    {"merged_length", c.merged_length},
                    {"width_at_parting", c.width}});
  return list;
}

json featuresJson(const FeatureReport& f, int64_t protectingBalls) {
  return {{"enabled", f.enabled},
          {"sharp_edge_polylines", f.sharp_edge_polylines},
          {"junction_polylines", f.junction_polylines},
          {"user_polylines", f.user_polylines},
          {"sharp_angle_deg", f.sharp_angle_deg},
          {"junctions", f.junctions},
          {"polylines", f.polylines},
          {"crossing_pieces", f.crossing_pieces},
          {"star_vertices", f.star_vertices},
          {"tangent_cusps", tangentCuspsJson(f.tangent_cusps)},
          {"protecting_ball_vertices", protectingBalls}};
}

json smallInputAnglesJson(const std::vector<SmallInputAngle>& smallAngles) {
  json angles = json::array();
  for (const SmallInputAngle& a : smallAngles)
    angles.push_back({{"kind", a.kind}, {"angle_deg", a.angle_deg}, {"location", a.location},
                      {"input", a.input}, {"edge", a.edge}});
  return angles;
}

json improvementJson(const ImprovementReport& r, const std::vector<SmallInputAngle>& smallAngles) {
  const ImprovementStats& s = r.stats;
  json poor = json::array();
  for (const PoorElement& e : r.poor.listed) {
    json entry = {{"tet", e.tet}, {"material", e.material}, {"min_dihedral_deg", e.min_dihedral},
                  {"location", e.location}};
    if (e.small_angle >= 0) {
      const SmallInputAngle& a = smallAngles[e.small_angle];
      entry["reason"] = "small input angle";
      entry["small_input_angle"] = {{"index", e.small_angle}, {"kind", a.kind}, {"angle_deg", a.angle_deg},
                                    {"location", a.location}, {"distance", e.small_angle_distance}};
    } else {
      entry["reason"] = s.stopped_by_time_limit ? "not improved in the time budget" : "not improved in the budget";
    }
    poor.push_back(entry);
  }
  return {{"enabled", r.enabled},
          {"min_dihedral_before_deg", s.min_dihedral_before},
          {"min_dihedral_after_deg", s.min_dihedral_after},
          {"operations", {{"flips23", s.flips23}, {"multi_face_removals", s.multi_face_removals}, {"flips32", s.flips32}, {"flips44", s.flips44},
                          {"edge_removals_5_to_7", s.edge_removals}, {"surface_flips", s.surface_flips}, {"edge_collapses", s.edge_collapses}, {"vertex_insertions", s.vertex_insertions}, {"smoothed_interior", s.smoothed_interior},
                          {"smoothed_surface", s.smoothed_surface}, {"smoothed_feature", s.smoothed_feature},
                          {"smoothed_curved_surface", s.smoothed_curved_surface},
                          {"smoothed_curved_feature", s.smoothed_curved_feature}}},
          {"curved_moves_largest_volume_share", s.curved_volume_share},
          {"flat_caps", {{"boundary_caps_removed", s.flat_caps.boundary_caps_removed},
                         {"interface_caps_flipped", s.flat_caps.interface_caps_flipped},
                         {"folds_removed", s.flat_caps.folds_removed},
                         {"caps_kept", s.flat_caps.caps_kept},
                         {"largest_volume_change", s.flat_caps.largest_volume_change},
                         {"curved_caps", s.flat_caps.curved_caps},
                         {"largest_curved_volume_change", s.flat_caps.largest_curved_volume_change}}},
          {"tets_before", {{"under_5_deg", s.before.under5}, {"under_10_deg", s.before.under10},
                           {"under_15_deg", s.before.under15}}},
          {"before_insertion", {{"min_dihedral_deg", s.min_dihedral_before_insertion},
                                {"under_5_deg", s.before_insertion.under5}, {"under_10_deg", s.before_insertion.under10},
                                {"under_15_deg", s.before_insertion.under15}}},
          {"passes", s.passes},
          {"stopped_by_time_limit", s.stopped_by_time_limit},
          {"seconds", s.seconds},
          {"tets_under_5_deg", r.poor.under5},
          {"tets_under_10_deg", r.poor.under10},
          {"tets_under_15_deg", r.poor.under15},
          {"tets_under_15_deg_near_small_input_angle", r.poor.near_small_angle},
          {"tets_under_15_deg_listed", poor}};
}

json boundarySnapJson(const SnapReport& s, double diagonal) {
  const BoundarySnapStatistics& snap = s.statistics;
  return {{"max_move", snap.max_move},
          {"max_move_relative", diagonal > 0 ? snap.max_move / diagonal : 0},
          {"vertices_moved", snap.moved},
          {"vertices_on_boundary_by_engine", snap.on_boundary_by_engine},
          {"vertices_kept_off_surface", snap.kept_off_surface},
          {"flat_surface_slivers_removed", snap.slivers_removed},
          {"flat_surface_slivers_kept_on_feature_edges", snap.slivers_kept_on_feature_edges},
          {"max_distance_kept_off_surface", snap.max_distance_kept},
          {"min_dihedral_before_deg", s.min_dihedral_before_deg}};
}

json inputsJson(const std::vector<InputReport>& inputs) {
  json materials = json::array();
  for (const InputReport& e : inputs)
    materials.push_back({{"name", e.name},
                         {"input", e.input},
                         {"kind", e.kind},
                         {"role", e.role == Role::Cut ? "cut" : "material"},
                         {"material", e.material},
                         {"source_volume", e.source_volume}});
  return materials;
}

// Parts are named as in report.inputs, so a user finds the interface of the two inputs they gave.
// One entry per pair: a pair that is not bonded also has the surface of its second side
// (material > other_material), listed under the pair's "surfaces".
json surfacesJson(const JobReport& r, const MaterialNames& names, bool interfaces) {
  json list = json::array();
  for (const SurfaceReport& s : r.surfaces) {
    if ((s.other_material != 0) != interfaces) continue;
    if (interfaces && s.material > s.other_material) continue;
    json entry = {{"name", s.name}, {"area", s.area}, {"triangles", s.triangles}};
    if (interfaces) {
      entry["parts"] = {materialName(names, s.material), materialName(names, s.other_material)};
      entry["materials"] = {s.material, s.other_material};
      const InterfaceBehaviour behaviour = r.interfaces.between(s.material, s.other_material);
      entry["kind"] = interfaceKindName(behaviour.kind);
      if (behaviour.kind == InterfaceKind::Contact) entry["friction"] = behaviour.friction;
      json sides = json::array({s.name});
      for (const SurfaceReport& back : r.surfaces)
        if (back.material == s.other_material && back.other_material == s.material) sides.push_back(back.name);
      entry["surfaces"] = sides;
      for (const JoinedAcrossGap& g : r.self_check.interface_gaps)
        if (g.material == s.material && g.other_material == s.other_material)
          entry["beyond_contact_area"] = g.beyond_contact_area;
      for (const InterfaceConstraint& c : r.interface_constraints)
        if (c.material == s.material && c.other_material == s.other_material) {
          entry["constraint"] = c.name;
          entry["master"] = c.master;
          entry["slave"] = c.slave;
          if (behaviour.kind == InterfaceKind::Tied) entry["position_tolerance"] = c.position_tolerance;
          if (!c.slave_nodes_name.empty()) {  // some slave nodes are shared with the master part
            entry["slave_node_surface"] = c.slave_nodes_name;
            entry["slave_nodes"] = c.slave_nodes.size();
          }
          if (behaviour.kind == InterfaceKind::Contact) entry["contact_stiffness"] = c.contact_stiffness;
        }
    } else {
      entry["part"] = materialName(names, s.material);
      entry["material"] = s.material;
    }
    list.push_back(entry);
  }
  return list;
}

// Under this smallest dihedral angle the report warns that a solver may reject elements.
constexpr double kFlatElementDeg = 0.1;

}  // namespace

MaterialNames partNames(const std::vector<InputReport>& inputs) {
  MaterialNames names;
  for (const InputReport& e : inputs) {
    if (e.role != Role::Material) continue;
    std::string& name = names[e.material];
    name += (name.empty() ? "" : "+") + e.name;
  }
  return names;
}

std::vector<SurfaceReport> describeSurfaces(const std::vector<MeshSurface>& surfaces, const MaterialNames& names) {
  std::vector<SurfaceReport> result;
  const std::vector<std::string> unique = surfaceNames(names, surfaces);
  for (size_t i = 0; i < surfaces.size(); ++i)
    result.push_back({surfaces[i].material, surfaces[i].other_material, unique[i], surfaces[i].area,
                      surfaces[i].faces.size()});
  return result;
}

void addMeshWarnings(JobReport& report) {
  const BoundarySnapStatistics& snap = report.boundary_snap.statistics;
  if (snap.kept_off_surface > 0) {
    std::ostringstream message;
    message << snap.kept_off_surface << " boundary node(s) stay up to " << snap.max_distance_kept
            << " from the CAD faces (worst near (" << snap.worst_kept[0] << ", " << snap.worst_kept[1] << ", "
            << snap.worst_kept[2] << ")): putting them on the faces would flatten or invert elements; FEM constraints "
               "on those faces may miss them (a finer edge_size near small input angles helps)";
    report.warnings.push_back(message.str());
  }
  const ConformityReport& conformity = report.conformity;
  if (conformity.inverted_tets > 0)
    report.warnings.push_back(std::to_string(conformity.inverted_tets) +
                              " tetrahedra are inverted (or fold, for tet10) after putting nodes on the CAD faces");
  if (!conformity.ok()) report.warnings.push_back("the mesh failed its conformity check (see report.conformity)");
  // Solvers reject elements this flat (CalculiX: "nonpositive jacobian") though their volume is
  // still positive, so the conformity check does not count them.
  if (report.counts.tets > 0 && report.quality.min_dihedral < kFlatElementDeg) {
    std::ostringstream message;
    message << "the mesh has elements with dihedral angles down to " << report.quality.min_dihedral
            << " degrees, which a solver may reject as flat (CalculiX: 'nonpositive jacobian'); see report.quality "
               "and report.thesis.slivers_left, and try finer sizes where the inputs meet at small angles";
    report.warnings.push_back(message.str());
  }
}

json reportJson(const JobReport& r) {
  json report;
  report["engine"] = engineName(r.engine);
  report["version"] = r.version;
  report["counts"] = countsJson(r.counts, r.quality);
  json volumes = json::object();
  for (const auto& [material, v] : r.quality.volume_per_material) volumes[std::to_string(material)] = v;
  report["volume_per_material"] = volumes;
  report["quality"] = qualityJson(r.quality);
  report["conformity"] = conformityJson(r.conformity);
  report["contact_tolerance"] = {{"value", r.contact_tolerance.value}, {"from", r.contact_tolerance.from}};
  report["self_check"] = selfCheckJson(r.self_check, r.checks);
  if (r.engine_run.thesis) {
    report["thesis"] = thesisJson(*r.engine_run.thesis, r.inputs);
    report["material_assignment"] = materialAssignmentName(r.material_assignment);
  }
  report["criteria"] = criteriaReportJson(r);
  report["features"] = featuresJson(r.features, r.engine_run.protecting_ball_vertices);
  report["small_input_angles"] = smallInputAnglesJson(r.small_input_angles);
  report["small_input_angle_limit_deg"] = r.small_input_angle_limit_deg;
  report["seeds_on_boundary"] = r.engine_run.seeds_on_boundary;
  report["boundary_snap"] = boundarySnapJson(r.boundary_snap, r.bbox_diagonal);
  report["improve"] = improvementJson(r.improve, r.small_input_angles);
  report["element_order"] = r.element_order;
  if (r.element_order == 2) report["second_order_straight_fallbacks"] = r.second_order_straight_fallbacks;
  report["bbox_diagonal"] = r.bbox_diagonal;
  report["inputs"] = inputsJson(r.inputs);
  const MaterialNames names = partNames(r.inputs);
  report["interfaces"] = surfacesJson(r, names, true);
  report["exteriors"] = surfacesJson(r, names, false);
  json keptJoined = json::array();
  for (const auto& [pair, kept] : r.interface_split.kept_joined) {
    json through = json::array();
    for (int b : kept.through) through.push_back(materialName(names, b));
    keptJoined.push_back({{"parts", {materialName(names, pair.first), materialName(names, pair.second)}},
                          {"nodes", kept.nodes},
                          {"through", through}});
  }
  report["interface_split"] = {{"corner_copies", r.interface_split.corner_copies},
                               {"mid_copies", r.interface_split.mid_copies},
                               {"kept_joined", keptJoined}};
  report["warnings"] = r.warnings;
  report["seconds"] = r.seconds;
  report["status"] = "done";
  return report;
}

namespace {

const char* jobEndName(JobEnd end) {
  switch (end) {
    case JobEnd::Stopped: return "stopped";
    case JobEnd::Cancelled: return "cancelled";
    case JobEnd::InputError: return "input_error";
    case JobEnd::FailedCheck: return "failed_check";
    case JobEnd::Error: break;
  }
  return "error";
}

}  // namespace

json unfinishedReportJson(const JobReport& r, const std::map<std::string, double>& seconds, JobEnd end,
                          const std::string& message, const std::string& phase) {
  json report;
  if (end == JobEnd::FailedCheck) {
    report = reportJson(r);
  } else {
    report["engine"] = engineName(r.engine);
    report["version"] = r.version;
    report["element_order"] = r.element_order;
    // report.inputs is filled late in the load phase, after the criteria and gaps it names.
    if (!r.inputs.empty()) {
      report["inputs"] = inputsJson(r.inputs);
      report["bbox_diagonal"] = r.bbox_diagonal;
      report["contact_tolerance"] = {{"value", r.contact_tolerance.value}, {"from", r.contact_tolerance.from}};
      report["criteria"] = criteriaReportJson(r);
    }
    if (seconds.count("features") && phase != "features") {
      report["features"] = featuresJson(r.features, r.engine_run.protecting_ball_vertices);
      report["small_input_angles"] = smallInputAnglesJson(r.small_input_angles);
      report["small_input_angle_limit_deg"] = r.small_input_angle_limit_deg;
    }
    report["warnings"] = r.warnings;
  }
  report["seconds"] = seconds;
  report["status"] = jobEndName(end);
  report["error"] = message;
  report["stopped_in"] = phase;
  return report;
}

void writeReportFile(const std::string& path, const json& report) {
  std::ofstream out(path);
  if (!out)
    throw Error("cannot write the report to '" + path + "': check that the folder exists and is writable (output.report)");
  out << report.dump(2) << "\n";
}

}  // namespace oraclemesh
