// The thesis engine (Rule Set T, issue 7): constrained segments end up as chains of mesh
// edges, restricted facets have their vertices on the boundary, cells meet their criteria or
// are listed, volumes match the Boolean composition, the run is deterministic and ends within
// its limits even for input angles under 60 degrees.
// CGAL before OpenCASCADE (OCCT's Handle macro breaks CGAL).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Tool.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "Error.h"
#include "demo_assembly_job.h"
#include "job/Pipeline.h"
#include "mesh/Quality.h"
#include "mesh_checks.h"
#include "occt_checks.h"
#include "small_angle_shapes.h"

namespace oraclemesh {
namespace {

using nlohmann::json;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

double circumradius(const TetMesh& m, size_t t) {
  std::array<K::Point_3, 4> p;
  for (int k = 0; k < 4; ++k) {
    const Point3& q = m.points[m.tets[t][k]];
    p[k] = K::Point_3(q[0], q[1], q[2]);
  }
  return std::sqrt(CGAL::squared_distance(CGAL::circumcenter(p[0], p[1], p[2], p[3]), p[0]));
}

double shortestEdge(const TetMesh& m, size_t t) {
  double shortest = std::numeric_limits<double>::infinity();
  for (const auto& e : test::kTetEdges)
    shortest = std::min(shortest, distance(m.points[m.tets[t][e[0]]], m.points[m.tets[t][e[1]]]));
  return shortest;
}

std::set<std::pair<int64_t, int64_t>> meshEdges(const TetMesh& m) {
  std::set<std::pair<int64_t, int64_t>> edges;
  for (const auto& t : m.tets)
    for (const auto& e : test::kTetEdges) edges.insert(std::minmax(t[e[0]], t[e[1]]));
  return edges;
}

// Meshing takes a second: each variant is meshed once and shared by the tests below.
// `optimize` false gives the engine's own output, before the CGAL sliver removal moves vertices
// (the perturber trades radius-edge ratios for dihedral angles, so the engine's criteria are
// checked on the mesh it made).
const JobResult& thesisDemo(int order, bool optimize = true) {
  static std::map<std::pair<int, bool>, JobResult> cache;
  auto it = cache.find({order, optimize});
  if (it == cache.end()) {
    nlohmann::json job = test::demoAssemblyJob(order, "thesis");
    job["optimize"] = optimize;
    it = cache.emplace(std::make_pair(order, optimize), runJob(JobSpec::fromJson(job, ""), RunControl())).first;
  }
  return it->second;
}

// The criteria checks of the engine, on the final (snapped) mesh: every cell within its
// material's bounds or near an element the report lists. The snap moves vertices on curved
// feature edges from the segment chords onto the curves (up to the chord's sagitta), which can
// flatten a sliver there: cells with such a vertex are not checked.
void expectCellsMeetCriteriaOrAreListed(const JobResult& r, const std::map<int, std::pair<double, double>>& bounds,
                                        double slack) {
  const TetMesh& m = r.mesh;
  const auto movedBySnap = [&](size_t t) {
    for (int k = 0; k < 4; ++k)
      if (m.vertex_dimension[m.tets[t][k]] == 1) return true;
    return false;
  };
  std::vector<Point3> listed;
  for (const auto& e : r.report.at("thesis").at("elements_left"))
    listed.push_back(e.at("location").get<Point3>());
  int64_t unexplained = 0;
  for (size_t t = 0; t < m.tets.size(); ++t) {
    if (movedBySnap(t)) continue;
    const auto [size, ratio] = bounds.at(m.tet_materials[t]);
    const double r0 = circumradius(m, t);
    if (r0 <= size * (1 + slack) && r0 / shortestEdge(m, t) <= ratio * (1 + slack)) continue;
    Point3 centroid{0, 0, 0};
    for (int k = 0; k < 4; ++k) centroid = centroid + 0.25 * m.points[m.tets[t][k]];
    const bool near = std::any_of(listed.begin(), listed.end(), [&](const Point3& p) { return distance(p, centroid) < 2 * size; });
    unexplained += !near;
  }
  // The listing keeps the worst 200: beyond that, the count must cover the rest.
  const int64_t listedCount = r.report.at("thesis").at("elements_left_total").get<int64_t>();
  EXPECT_TRUE(unexplained == 0 || listedCount > 200) << unexplained << " cells fail their criteria unlisted";
}

TEST(ThesisEngine, SphereMeetsCriteriaWithBoundaryOnSphere) {
  const json job = {{"inputs", {{{"name", "Ball"}, {"sphere", {{"center", {1, 2, 3}}, {"radius", 5}}}, {"material", 1}}}},
                    {"criteria", {{"default", {{"cell_size", 1.5}, {"facet_size", 1.5}, {"facet_distance", 0.05}}}}},
                    {"engine", "thesis"},
                    {"optimize", false},  // the engine's own criteria, before sliver removal
                    {"element_order", 1},
                    {"checks", "warn"}};  // tet4 chords: 1.5 % short of the sphere
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  const TetMesh& m = r.mesh;
  const json& check = r.report.at("thesis").at("final_check");
  EXPECT_EQ(check.at("restricted_facets_off_boundary"), 0);
  for (int64_t v : test::boundaryNodes(m))
    EXPECT_NEAR(distance(m.points[v], {1, 2, 3}), 5, 1e-9 * 10) << "boundary node off the sphere";
  const double volume = test::volumePerMaterial(m).at(1);
  const double exact = 4.0 / 3.0 * M_PI * 125;
  // Chords of facets within facet_distance 0.05 of a radius-5 sphere: about 2 % under.
  EXPECT_NEAR(volume, exact, 0.03 * exact);
  EXPECT_LT(volume, exact);
  expectCellsMeetCriteriaOrAreListed(r, {{1, {1.5, 2.0}}}, 1e-6);
  const json& rules = r.report.at("thesis").at("rule_insertions");
  EXPECT_GT(rules.value("T2.2", 0), 0);
  EXPECT_GT(rules.value("T3.4", 0) + rules.value("T3.3", 0), 0);
}

TEST(ThesisEngine, DemoAssemblySegmentsAreUnencroachedChainsOfEdges) {
  const JobResult& r = thesisDemo(1);
  const TetMesh& m = r.mesh;
  const json& thesis = r.report.at("thesis");
  EXPECT_EQ(thesis.at("final_check").at("subsegments_not_edges"), 0);
  EXPECT_EQ(thesis.at("final_check").at("encroached_subsegments"), 0);
  EXPECT_EQ(thesis.at("final_check").at("restricted_facets_off_boundary"), 0);
  EXPECT_GT(thesis.at("star_vertices").get<int>(), 0);
  EXPECT_GT(thesis.at("rule_insertions").value("T1.1", 0), 0);
  // Every feature edge is a mesh edge, and the edges of one curve form chains (no vertex
  // has more than two edges of the same curve).
  ASSERT_GT(m.feature_edges.size(), 20u);
  const auto edges = meshEdges(m);
  std::map<std::pair<int, int64_t>, int> degree;
  for (size_t i = 0; i < m.feature_edges.size(); ++i) {
    const auto& e = m.feature_edges[i];
    EXPECT_TRUE(edges.count(std::minmax(e[0], e[1]))) << "feature edge is not a mesh edge";
    ++degree[{m.feature_edge_curves[i], e[0]}];
    ++degree[{m.feature_edge_curves[i], e[1]}];
  }
  for (const auto& [key, d] : degree) EXPECT_LE(d, 2) << "curve " << key.first << " branches";
  // Every curve the pipeline found is present.
  std::set<int> curves(m.feature_edge_curves.begin(), m.feature_edge_curves.end());
  EXPECT_EQ(static_cast<int>(curves.size()), r.report.at("features").at("polylines").get<int>());
}

TEST(ThesisEngine, DemoAssemblyVolumesNodesAndCriteria) {
  const test::DemoAssembly a;
  const double pinVolume = test::volumeOf(a.pin);
  const double plateVolume = test::volumeOf(BRepAlgoAPI_Cut(BRepAlgoAPI_Cut(a.plate, a.pin).Shape(), a.cut).Shape());
  // Second order, as the demo assembly's own volume test: tet10 mid nodes on the cylinder
  // take the chord error out of the volumes.
  const std::map<int, double> volumes = test::volumePerMaterial(thesisDemo(2).mesh);
  ASSERT_EQ(volumes.size(), 2u);
  EXPECT_NEAR(volumes.at(1), pinVolume, 0.005 * pinVolume);
  EXPECT_NEAR(volumes.at(2), plateVolume, 0.005 * plateVolume);
  const JobResult& r = thesisDemo(1);
  const TetMesh& m = r.mesh;
  const TopoDS_Compound all = test::compoundOf({a.pin, a.plate, a.cut});
  double worst = 0;
  for (int64_t v : test::boundaryNodes(m)) worst = std::max(worst, test::distanceToShape(m.points[v], all));
  EXPECT_LT(worst, 1e-9 * 120);
  const test::Conformity c = test::conformity(m);
  EXPECT_EQ(c.faces_shared_by_more_than_two, 0);
  EXPECT_EQ(c.open_boundary_edges, 0);
  EXPECT_EQ(c.inverted, 0);
  expectCellsMeetCriteriaOrAreListed(thesisDemo(1, false), {{1, {3.0, 2.0}}, {2, {5.0, 2.0}}}, 1e-6);
  std::cout << "[figures] thesis demo: pin " << volumes.at(1) << " vs " << pinVolume << ", plate " << volumes.at(2)
            << " vs " << plateVolume << ", boundary nodes off faces <= " << worst << "\n";
}

// The engine records, for its surface vertices, the input whose boundary it put them on (an
// oracle crossing or projection), and the snap takes them as they are: each must lie on that
// input's faces, by OpenCASCADE's measure (a wrong entry puts it millimetres away).
TEST(ThesisEngine, RecordedBoundaryEntriesAreOnThatInputsFaces) {
  const test::DemoAssembly a;
  const std::map<std::string, TopoDS_Shape> shapeOf = {{"Pin", a.pin}, {"CutCorner", a.cut}, {"Plate", a.plate}};
  const JobResult& r = thesisDemo(1);
  const TetMesh& m = r.mesh;
  const json& entries = r.report.at("inputs");  // one per oracle entry, in entry order
  ASSERT_EQ(m.vertex_boundary_entry.size(), m.points.size());
  const double diagonal = r.report.at("bbox_diagonal").get<double>();
  int64_t recorded = 0, onSurface = 0;
  std::map<std::string, int64_t> perInput;
  double worst = 0;
  for (size_t v = 0; v < m.points.size(); ++v) {
    onSurface += m.vertex_dimension[v] == 2;
    const int e = m.vertex_boundary_entry[v];
    if (e < 0) continue;
    EXPECT_EQ(m.vertex_dimension[v], 2) << "vertex " << v;
    ASSERT_LT(e, static_cast<int>(entries.size()));
    const std::string name = entries[e].at("name").get<std::string>();
    ASSERT_TRUE(shapeOf.count(name)) << name;
    const double d = test::distanceToShape(m.points[v], shapeOf.at(name));
    EXPECT_LE(d, 1e-9 * diagonal) << "vertex " << v << " recorded on " << name;
    worst = std::max(worst, d);
    ++recorded;
    ++perInput[name];
  }
  // Nearly all surface vertices come from crossings (the rest go through the projection).
  EXPECT_GT(recorded, 0.9 * onSurface);
  // The snap counted them before the improvement stage, whose edge collapses remove vertices.
  const int64_t counted = r.report.at("boundary_snap").at("vertices_on_boundary_by_engine").get<int64_t>();
  EXPECT_LE(recorded, counted);
  EXPECT_GE(recorded, counted - r.report.at("improve").at("operations").at("edge_collapses").get<int64_t>());
  EXPECT_GT(perInput["Pin"], 0);
  EXPECT_GT(perInput["Plate"], 0);
  std::cout << "[figures] thesis demo: " << recorded << " of " << onSurface
            << " surface vertices on a recorded input's faces (worst " << worst << "), snap moved "
            << r.report.at("boundary_snap").at("vertices_moved") << ", slivers the engine left "
            << r.report.at("thesis").at("slivers_left_total") << "\n";
}

// The same job on both engines: the thesis engine gives the same mesh twice, and Mesh_3's
// mesh of it is a valid mesh of the same parts. Linear tets: the pin's cylinder (radius r = 5,
// facet distance d = 0.05 for the pin) is the only curved face, and each engine replaces it by
// triangles with their corners on it, each at most about d from it. Chords of sagitta d
// around a circle of radius r cut off (4/3)(d/r) of its area, so each engine's pin lies
// between (1 - (4/3) d/r) V and V of the exact pin volume V, and their pins differ by at most
// (4/3)(d/r) V (1.3 %); the plate takes what the pin loses inside it (a third of the pin's
// height), its other faces are planes, met exactly.
TEST(ThesisEngine, SameJobSameMeshAndFiguresAgainstMesh3) {
  const JobResult& first = thesisDemo(1);
  const auto t0 = std::chrono::steady_clock::now();
  const JobResult again = runJob(JobSpec::fromJson(test::demoAssemblyJob(1, "thesis"), ""), RunControl());
  const double thesisSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(again.mesh.points, first.mesh.points);
  EXPECT_EQ(again.mesh.tets, first.mesh.tets);
  json cgalJob = test::demoAssemblyJob(1, "cgal");
  const auto t1 = std::chrono::steady_clock::now();
  const JobResult cgal = runJob(JobSpec::fromJson(cgalJob, ""), RunControl());
  const double cgalSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();

  EXPECT_EQ(cgal.report.at("engine"), "cgal");
  ASSERT_GT(cgal.mesh.tets.size(), 1000u);
  ASSERT_EQ(cgal.mesh.tet_materials.size(), cgal.mesh.tets.size());
  const test::Conformity c = test::conformity(cgal.mesh);
  EXPECT_EQ(c.inverted, 0) << "Mesh_3 tets with det J <= 0";
  EXPECT_EQ(c.faces_shared_by_more_than_two, 0);
  EXPECT_EQ(c.open_boundary_edges, 0);
  const std::map<int, double> cgalVolumes = test::volumePerMaterial(cgal.mesh);
  const std::map<int, double> thesisVolumes = test::volumePerMaterial(again.mesh);
  ASSERT_EQ(cgalVolumes.size(), 2u);
  ASSERT_EQ(thesisVolumes.size(), 2u);
  const test::DemoAssembly a;
  const double pinVolume = test::volumeOf(a.pin);
  const double plateVolume = test::volumeOf(BRepAlgoAPI_Cut(BRepAlgoAPI_Cut(a.plate, a.pin).Shape(), a.cut).Shape());
  const double radius = 5, facetDistance = cgalJob["criteria"]["materials"]["1"]["facet_distance"].get<double>();
  const double chordLoss = 4.0 / 3.0 * facetDistance / radius * pinVolume;
  EXPECT_NEAR(cgalVolumes.at(1), thesisVolumes.at(1), chordLoss);
  EXPECT_NEAR(cgalVolumes.at(2), thesisVolumes.at(2), chordLoss / 3);
  for (const auto* volumes : {&cgalVolumes, &thesisVolumes}) {
    EXPECT_LT(volumes->at(1), pinVolume);
    EXPECT_GT(volumes->at(1), pinVolume - chordLoss);
    EXPECT_GT(volumes->at(2), plateVolume);
    EXPECT_LT(volumes->at(2), plateVolume + chordLoss / 3);
  }
  // Mesh_3 with its sliver perturbation and exudation (the job's default optimize) leaves
  // 4.4 degrees here; a sliver it failed to remove would be near 0.
  double smallest = 180;
  for (const auto& t : cgal.mesh.tets) {
    const auto angles = dihedralAngles(cgal.mesh.points[t[0]], cgal.mesh.points[t[1]], cgal.mesh.points[t[2]],
                                       cgal.mesh.points[t[3]]);
    smallest = std::min(smallest, *std::min_element(angles.begin(), angles.end()));
  }
  EXPECT_GT(smallest, 3.0);
  EXPECT_NEAR(cgal.report.at("quality").at("min_dihedral_deg").get<double>(), smallest, 1e-9);
  std::cout << "[figures] demo assembly volumes, thesis / cgal / exact: pin " << thesisVolumes.at(1) << " / "
            << cgalVolumes.at(1) << " / " << pinVolume << ", plate " << thesisVolumes.at(2) << " / "
            << cgalVolumes.at(2) << " / " << plateVolume << "\n";
  std::cout << "[figures] demo assembly, same criteria: thesis " << again.mesh.tets.size() << " tets, "
            << again.mesh.points.size() << " vertices, " << thesisSeconds << " s (min dihedral "
            << again.report["quality"]["min_dihedral_deg"] << "); cgal " << cgal.mesh.tets.size()
            << " tets, " << cgal.mesh.points.size() << " vertices, " << cgalSeconds << " s (min dihedral "
            << cgal.report["quality"]["min_dihedral_deg"] << "); refinement alone: thesis " << again.report["seconds"]["thesis"]
            << " s, Mesh_3 " << cgal.report["seconds"]["mesh3_refine"] << " s\n";
  std::cout << "[figures] thesis rules: " << again.report["thesis"]["rule_insertions"].dump() << "\n";
  json featureless = test::demoAssemblyJob(1, "thesis");
  featureless["features"] = false;
  const JobResult plain = runJob(JobSpec::fromJson(featureless, ""), RunControl());
  EXPECT_EQ(plain.report["thesis"]["star_vertices"], 0);
  EXPECT_TRUE(plain.mesh.feature_edges.empty());
  std::cout << "[figures] thesis featureless: " << plain.mesh.tets.size() << " tets, " << plain.mesh.points.size()
            << " vertices, " << plain.report["seconds"]["thesis"] << " s in the engine\n";
}

// A tray with rounded corners (box 12 x 9 x 3, vertical edges filleted, radius 2), as the
// implant_in_bone example's: its top and bottom outlines are straight edges continued
// tangentially by arcs. Their 8 + 8 joints are polyline ends shared by two curves, but not star
// vertices for the engine (segments meeting at 180 degrees cannot encroach each other), so
// no T1.1 piece of l_min,i / 3 refines the mesh there; Q1 is applied once (the pipeline does
// not equalise for this engine), and the arcs are sampled to the facet distance, not finer.
TEST(ThesisEngine, TangentJointsOfARoundedTrayAreNotStarVertices) {
  BRepPrimAPI_MakeBox box(gp_Pnt(0, 0, 0), 12, 9, 3);
  BRepFilletAPI_MakeFillet fillet(box.Shape());
  for (TopExp_Explorer e(box.Shape(), TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
    TopExp_Explorer v(edge, TopAbs_VERTEX);
    const gp_Pnt a = BRep_Tool::Pnt(TopoDS::Vertex(v.Current()));
    v.Next();
    const gp_Pnt b = BRep_Tool::Pnt(TopoDS::Vertex(v.Current()));
    if (std::abs(a.Z() - b.Z()) > 1) fillet.Add(2.0, edge);
  }
  const double edgeSize = 1, facetDistance = 0.1;
  json job = {{"inputs", {{{"name", "Tray"}, {"brep", test::brepText(fillet.Shape())}, {"material", 1}}}},
              {"criteria",
               {{"default",
                 {{"cell_size", 1.5}, {"facet_size", 1.5}, {"facet_distance", facetDistance}, {"edge_size", edgeSize}}}}},
              {"engine", "thesis"},
              // Rule Set T alone: the sliver rule (sliver removal) may split subsegments as well, which
              // is not what this test is about.
              {"optimize", {{"perturb", false}, {"exude", false}}},
              {"element_order", 1},
              {"seed", 0}};
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_EQ(r.report.at("features").at("star_vertices").get<int>(), 16);
  EXPECT_EQ(r.report.at("thesis").at("star_vertices").get<int>(), 0);
  EXPECT_EQ(r.report.at("thesis").at("rule_insertions").value("T1.1", 0), 0);
  const json& check = r.report.at("thesis").at("final_check");
  EXPECT_EQ(check.at("subsegments_not_edges"), 0);
  EXPECT_EQ(check.at("encroached_subsegments"), 0);
  // Arcs of radius 2 at a sagitta of 0.02 mm (the Mesh_3 engine's bound) would be sampled at
  // 0.39 mm, and the old double Q1 left pieces of l_min,i / 9 at the joints.
  double shortest = std::numeric_limits<double>::infinity();
  for (const auto& e : r.mesh.feature_edges) shortest = std::min(shortest, distance(r.mesh.points[e[0]], r.mesh.points[e[1]]));
  ASSERT_FALSE(r.mesh.feature_edges.empty());
  EXPECT_GT(shortest, 0.45 * edgeSize) << "constrained subsegments refined below 0.45 edge_size";
  const double exact = test::volumeOf(fillet.Shape());
  EXPECT_NEAR(test::volumePerMaterial(r.mesh).at(1), exact, 0.005 * exact);
}

// Rule Set T bounds radius-edge ratios, not dihedral angles: sliver removal (the sliver rule and
// rule P in the engine) must lift the worst dihedral angle of the final, snapped
// mesh to 12 degrees (issue 7) and keep every constrained subsegment and the boundary.
TEST(ThesisEngine, SliverRemovalReachesTwelveDegreesKeepingSegments) {
  const JobResult& raw = thesisDemo(1, false);
  const JobResult& optimized = thesisDemo(1, true);
  const double before = raw.report["quality"]["min_dihedral_deg"].get<double>();
  const double after = optimized.report["quality"]["min_dihedral_deg"].get<double>();
  EXPECT_GE(after, 12.0) << "sliver removal did not reach 12 degrees (from " << before << ")";
  const json& thesis = optimized.report.at("thesis");
  EXPECT_GT(thesis.at("rule_insertions").value("sliver.near_centre", 0), 0) << "the sliver rule did not act";
  EXPECT_EQ(raw.report.at("thesis").at("rule_insertions").value("sliver.near_centre", 0), 0)
      << "the sliver rule runs without optimize";
  // Rule P moves corners of the slivers the sliver rule left; the final checks below hold after it.
  EXPECT_GT(thesis.at("vertex_moves").get<int64_t>(), 0) << "rule P moved no vertex";
  EXPECT_EQ(raw.report.at("thesis").at("vertex_moves").get<int64_t>(), 0) << "rule P runs without optimize";
  // The sliver rule inserts points, so T1-T3 still hold afterwards, and every subsegment (it splits
  // some) is a mesh edge of the final mesh.
  EXPECT_EQ(thesis.at("final_check").at("subsegments_not_edges"), 0);
  EXPECT_EQ(thesis.at("final_check").at("encroached_subsegments"), 0);
  EXPECT_EQ(thesis.at("final_check").at("restricted_facets_off_boundary"), 0);
  ASSERT_GE(static_cast<int64_t>(optimized.mesh.feature_edges.size()), raw.report.at("thesis").at("constrained_subsegments").get<int64_t>());
  const auto edges = meshEdges(optimized.mesh);
  int64_t missing = 0;
  for (const auto& e : optimized.mesh.feature_edges) missing += !edges.count(std::minmax(e[0], e[1]));
  EXPECT_EQ(missing, 0) << "feature edges are not mesh edges after sliver removal";
  // Segment vertices lie on the pin's circles already: the snap costs no quality (the
  // improvement stage after it may only add).
  const double afterSnap = optimized.report.at("improve").at("min_dihedral_before_deg").get<double>();
  EXPECT_NEAR(optimized.report["boundary_snap"]["min_dihedral_before_deg"].get<double>(), afterSnap, 0.1);
  EXPECT_GE(after, afterSnap);
  const test::Conformity c = test::conformity(optimized.mesh);
  EXPECT_EQ(c.open_boundary_edges, 0);
  EXPECT_EQ(c.inverted, 0);
  std::cout << "[figures] thesis demo sliver removal: min dihedral " << before << " -> " << after << " deg, tets "
            << raw.mesh.tets.size() << " -> " << optimized.mesh.tets.size() << ", rules "
            << thesis.at("rule_insertions").dump() << ", seconds " << optimized.report["seconds"].dump() << "\n";
}

// Rule P (vertex moves on the engine's own triangulation) lifts every cell of the demo over
// the engine's sliver target (the job's sliver bound, default 10, + 5 degrees); no other
// stage removes slivers (before the Delaunay-first screen, rule P left 3 slivers here and
// CGAL's perturbation, since removed, ran after the engine).
TEST(ThesisEngine, RulePLiftsEveryDemoCellOverTheSliverTarget) {
  const JobResult& r = thesisDemo(1, true);
  const json& thesis = r.report.at("thesis");
  EXPECT_TRUE(thesis.at("slivers_left").empty()) << thesis.at("slivers_left").dump();
  EXPECT_EQ(thesis.at("slivers_left_total").get<int64_t>(), 0);
  EXPECT_GT(thesis.at("vertex_moves").get<int64_t>(), 0);
  // The sliver rule's and rule P's seconds are the engine's phases.
  const json& seconds = r.report.at("seconds");
  EXPECT_GT(seconds.value("thesis_sliver_rule", 0.0), 0) << seconds.dump();
  EXPECT_GT(seconds.value("thesis_vertex_moves", 0.0), 0) << seconds.dump();
  // Measured from the final tets: the snap keeps segment vertices on the pin's circles, so
  // the engine's target holds on the final mesh too.
  const double target = JobSpec().sliver_bound + 5;
  double smallest = 180;
  for (const auto& t : r.mesh.tets) {
    const auto angles = dihedralAngles(r.mesh.points[t[0]], r.mesh.points[t[1]], r.mesh.points[t[2]], r.mesh.points[t[3]]);
    smallest = std::min(smallest, *std::min_element(angles.begin(), angles.end()));
  }
  EXPECT_GE(smallest, target);
  EXPECT_GE(r.report.at("boundary_snap").at("min_dihedral_before_deg").get<double>(), target);
  // The moves keep Rule Set T's guarantees: every constrained subsegment an unencroached
  // mesh edge, every restricted facet on boundary vertices.
  EXPECT_EQ(thesis.at("final_check").at("subsegments_not_edges"), 0);
  EXPECT_EQ(thesis.at("final_check").at("encroached_subsegments"), 0);
  EXPECT_EQ(thesis.at("final_check").at("restricted_facets_off_boundary"), 0);
  const auto edges = meshEdges(r.mesh);
  ASSERT_GE(static_cast<int64_t>(r.mesh.feature_edges.size()), thesis.at("constrained_subsegments").get<int64_t>());
  for (const auto& e : r.mesh.feature_edges) EXPECT_TRUE(edges.count(std::minmax(e[0], e[1]))) << e[0] << "-" << e[1];
}

TEST(ThesisEngine, SmallAnglesTerminateWithinLimits) {
  const double radius = 3, height = 15;
  const json job = {
      {"inputs",
       {{{"name", "Wedge"}, {"brep", test::brepText(test::wedge(10, 30, 8))}, {"material", 1}},
        {{"name", "Spike"}, {"brep", test::brepText(test::coneWithTip(gp_Pnt(40, 0, 0), radius, height))}, {"material", 2}}}},
      {"criteria", {{"default", {{"cell_size", 3}, {"facet_size", 3}, {"facet_distance", 0.3}, {"edge_size", 1.5}}},
                    {"materials", {{"2", {{"facet_size", 1.5}, {"facet_distance", 0.05}}}}}}},
      {"engine", "thesis"},
      {"element_order", 1},
      {"checks", "warn"},  // the wedge's thin edge comes out in pieces at these sizes
      {"limits", {{"max_vertices", 200000}, {"time_limit", 60}}}};
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  const std::map<int, double> volumes = test::volumePerMaterial(r.mesh);
  const double wedgeVolume = 0.5 * 30 * 30 * std::tan(10 * test::kDegree) * 8;
  const double coneVolume = M_PI * radius * radius * height / 3;
  EXPECT_NEAR(volumes.at(1), wedgeVolume, 0.02 * wedgeVolume);
  EXPECT_NEAR(volumes.at(2), coneVolume, 0.03 * coneVolume);
  EXPECT_EQ(r.report.at("thesis").at("final_check").at("encroached_subsegments"), 0);
  // The terminator leaves elements only at the small angles: along the wedge's 10-degree edge
  // (the z axis from 0 to 8) or at the cone's tip (40, 0, 15), within the reach the engine
  // gives a small angle (4 subsegment lengths, 6 mm at edge_size 1.5). Facets in the
  // 10-degree corners of the wedge's top and bottom faces keep a small angle while the face
  // is narrower than edge_size (within 8.5 mm of the edge); since T2.1 leaves those that
  // fail the facet angle alone, they and the cells on them stay coarser, up to 3.6 mm out.
  for (const auto& e : r.report.at("thesis").at("elements_left")) {
    const Point3 p = e.at("location").get<Point3>();
    const double toEdge = distance(p, {0, 0, std::clamp(p[2], 0.0, 8.0)});
    EXPECT_LT(std::min(toEdge, distance(p, {40, 0, height})), 6.0) << e.dump();
    EXPECT_FALSE(e.at("reason").get<std::string>().empty());
  }
  std::cout << "[figures] wedge + cone, thesis: " << r.mesh.points.size() << " vertices, "
            << r.report["thesis"]["rule_insertions"].dump() << ", " << r.report["seconds"]["thesis"] << " s\n";
}

TEST(ThesisEngine, VertexLimitStopsWithLimitErrorAndPartialMesh) {
  json job = test::demoAssemblyJob(1, "thesis");
  job["limits"] = {{"max_vertices", 300}};
  job["criteria"]["fineness"] = "off";  // the limit is met while refining, not by the field's estimate
  job["criteria"]["default"]["cell_size"] = 50;  // pass the up-front size estimate
  job["criteria"]["materials"]["1"]["cell_size"] = 50;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "oraclemesh_thesis_vertex_limit";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  job["output"] = {{"files", {(dir / "mesh.vtu").string()}}, {"report", (dir / "report.json").string()}};
  std::string message;
  try {
    runJob(JobSpec::fromJson(job, ""), RunControl());
    ADD_FAILURE() << "no LimitError";
  } catch (const LimitError& e) {
    message = e.what();
    EXPECT_NE(message.find("max_vertices"), std::string::npos) << message;
    EXPECT_NE(message.find("mesh.partial.vtu"), std::string::npos) << message;
  }
  // The mesh so far is written for inspection, the requested file is not.
  EXPECT_GT(std::filesystem::file_size(dir / "mesh.partial.vtu"), 1000u);
  EXPECT_FALSE(std::filesystem::exists(dir / "mesh.vtu"));
  // So is a report that says where the job stopped and what it had found by then.
  std::ifstream in(dir / "report.json");
  ASSERT_TRUE(in) << "no report written for the stopped job";
  const json report = json::parse(in);
  EXPECT_EQ(report.at("status"), "stopped");
  EXPECT_EQ(report.at("stopped_in"), "thesis");
  EXPECT_EQ(report.at("error"), message);
  EXPECT_EQ(report.at("inputs").size(), 3u);
  EXPECT_EQ(report.at("criteria").at("materials").at("1").at("cell_size"), 50);
  EXPECT_TRUE(report.contains("small_input_angles"));
  const json& seconds = report.at("seconds");
  for (const char* phase : {"load", "features", "thesis", "thesis_initial_points"})
    EXPECT_TRUE(seconds.contains(phase)) << phase << ": " << seconds.dump();
  EXPECT_FALSE(seconds.contains("snap")) << seconds.dump();
  EXPECT_FALSE(report.contains("counts")) << "no mesh was finished";
  std::filesystem::remove_all(dir);
}

TEST(ThesisEngine, TimeLimitStopsRefinementWithLimitError) {
  // The time limit runs out while the engine refines: when it reports the refine phase, the
  // progress callback waits for the limit; the engine's next checkpoint must throw.
  RunControl* controlPointer = nullptr;
  bool refining = false;
  RunControl control(
      [&](const std::string& phase, double) {
        if (phase != "refine" || refining) return;
        refining = true;
        while (controlPointer->remainingSeconds() > 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      },
      2.0);
  controlPointer = &control;
  EXPECT_THROW(runJob(JobSpec::fromJson(test::demoAssemblyJob(1, "thesis"), ""), control), LimitError);
  EXPECT_TRUE(refining);
}

TEST(ThesisEngine, JobOptionsOfTheThesisEngine) {
  json job = test::demoAssemblyJob(1, "thesis");
  job["material_assignment"] = "barycenter";
  job["initial_points"] = {{20, 20, 5}};
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_EQ(r.report.at("material_assignment"), "barycenter");
  const double target[3] = {20, 20, 5};
  const bool present = std::any_of(r.mesh.points.begin(), r.mesh.points.end(), [&](const Point3& p) {
    return p[0] == target[0] && p[1] == target[1] && p[2] == target[2];
  });
  EXPECT_TRUE(present) << "the initial point is a mesh vertex";
  job["engine"] = "cgal";
  EXPECT_THROW(JobSpec::fromJson(job, ""), InputError);
}

}  // namespace
}  // namespace oraclemesh
