// The thesis engine on the shared CAD models at default sizes (the sweep of
// tests/bench/engine_sweep.py), for the cases that went wrong there.
// CGAL before OpenCASCADE (OCCT's Handle macro breaks CGAL).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <set>
#include <utility>
#include <nlohmann/json.hpp>

#include "domain/BrepSolid.h"
#include "improve/TetShape.h"
#include "job/Pipeline.h"
#include "mesh_checks.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

using nlohmann::json;

// 6 V / l_min^3: 0.71 for a regular tetrahedron, 0 for four coplanar corners (the engine's
// flat-cell measure).
double flatness(const TetMesh& m, size_t t) {
  double shortest = std::numeric_limits<double>::infinity();
  for (const auto& e : test::kTetEdges)
    shortest = std::min(shortest, distance(m.points[m.tets[t][e[0]]], m.points[m.tets[t][e[1]]]));
  return 6 * std::abs(test::tetVolume(m, t)) / (shortest * shortest * shortest);
}

// No face shared by three tets, no open material boundary, no inverted tet.
void expectConforming(const TetMesh& m) {
  const test::Conformity c = test::conformity(m);
  EXPECT_EQ(c.faces_shared_by_more_than_two, 0);
  EXPECT_EQ(c.open_boundary_edges, 0);
  EXPECT_EQ(c.inverted, 0);
}

// A shared model's one solid, meshed at the diagonal's sizes (fineness off, the default these
// regressions were found at) with sharp edges by the thesis engine, with the B-rep volume to
// compare against. `extra` adds or overrides job keys.
struct SharedModelRun {
  double brep_volume = 0;
  JobResult result;
};
SharedModelRun meshSharedModel(const std::string& fileName, const std::string& name, const json& extra) {
  const std::string file = test::cadDir() + "/" + fileName;
  const auto loaded = BrepSolid::loadFile(file, name, BrepSolid::Grouping::Separate);
  EXPECT_EQ(loaded.solids.size(), 1u) << fileName;
  json job = {{"inputs", {{{"name", name}, {"file", file}, {"material", 1}}}},
              {"criteria", {{"fineness", "off"}}},
              {"engine", "thesis"},
              {"features", {{"sharp_angle_deg", 30}}},
              {"element_order", 1},
              {"checks", "warn"},  // tet4 at these sizes: volumes are checked where they matter
              {"seed", 0}};
  job.update(extra);
  return {test::volumeOf(loaded.solids.at(0)->shape()), runJob(JobSpec::fromJson(job, ""), RunControl())};
}

// Every boundary node of the run's mesh on the part in `fileName` (1e-9 of the diagonal, the
// snap's guarantee; 1e-6 here for OpenCASCADE's own distance).
void expectBoundaryNodesOnTheCad(const SharedModelRun& run, const std::string& fileName) {
  const TetMesh& m = run.result.mesh;
  const auto loaded = BrepSolid::loadFile(test::cadDir() + "/" + fileName, "part", BrepSolid::Grouping::Separate);
  const double tolerance = 1e-6 * run.result.report.at("bbox_diagonal").get<double>();
  std::set<int64_t> onBoundary;
  for (const BoundaryTriangle& b : m.boundary) onBoundary.insert(b.v.begin(), b.v.end());
  int64_t off = 0;
  for (int64_t v : onBoundary) off += !(test::distanceToShape(m.points[v], loaded.solids.at(0)->shape()) <= tolerance);
  EXPECT_EQ(off, 0) << "of " << onBoundary.size() << " boundary nodes";
}

// U_Joint_2.stp has two parallel feature circles 25.4 mm apart (y = +-12.7, the ends of a
// cylindrical face) whose samples pair up into four (nearly) coplanar, cocircular points. Their flat cell's circumcentre is
// anywhere on the circle's axis: rounding put it 20 mm away, where T3.4 inserted a stray vertex
// next to a face (its facets then read 22x over facet_distance, left), and the flat cell
// itself stayed in the mesh (0.000000000000004 degrees after the snap). The engine now refines
// a flat cell at its centroid, which always removes it.
TEST(ThesisSharedModels, UJointFlatCellBetweenParallelEdgesIsRefined) {
  // Default sizes and sharp edges, the engine's refinement alone (no sliver rule or rule P,
  // which do not move feature vertices and so could not have opened the flat cell either).
  const SharedModelRun run = meshSharedModel("U_Joint_2.stp", "UJoint", {{"optimize", {{"perturb", false}}}});
  const double brepVolume = run.brep_volume;
  const JobResult& r = run.result;
  const TetMesh& m = r.mesh;

  double flattest = std::numeric_limits<double>::infinity();
  for (size_t t = 0; t < m.tets.size(); ++t) flattest = std::min(flattest, flatness(m, t));
  EXPECT_GT(flattest, 1e-4) << "a flat cell is left in the mesh";
  const json& thesis = r.report.at("thesis");
  for (const json& e : thesis.at("elements_left"))
    EXPECT_EQ(e.at("reason").get<std::string>().find("flat cell"), std::string::npos) << e.dump();
  EXPECT_EQ(thesis.at("elements_left").size(), 0u) << thesis.at("elements_left").dump();
  const json& check = thesis.at("final_check");
  EXPECT_EQ(check.at("subsegments_not_edges").get<int>(), 0);
  EXPECT_EQ(check.at("encroached_subsegments").get<int>(), 0);
  EXPECT_EQ(check.at("restricted_facets_off_boundary").get<int>(), 0);
  expectConforming(m);
  // tet4 at the default facet distance (diagonal / 150): chords of the curved faces cost < 1 %.
  const double meshed = test::volumePerMaterial(m).at(1);
  EXPECT_NEAR(meshed, brepVolume, 0.01 * brepVolume);
  std::cout << "[figures] U_Joint_2 thesis tet4: " << m.tets.size() << " tets, volume " << meshed << " vs B-rep "
            << brepVolume << " (" << 100 * (meshed - brepVolume) / brepVolume << " %), flattest cell " << flattest
            << ", min dihedral " << r.report.at("quality").at("min_dihedral_deg") << "\n";
}

// part.step has two pairs of feature curves that leave a vertex tangentially (a line tangent
// to an arc of radius 25.4 mm at (85.725, +-25.4, 42.875 / 61.925), 0 degrees; an arc tangent
// to a spline at (56.925, +-7.9375, 61.924), 0.15 degrees). Next to them every vertex on one
// curve encroached the other's subsegments and T1.2's midpoint splits answered each other
// down to 0.017 mm pieces; each close pair of segment vertices made slivers that neither rule
// S nor CGAL's perturbation (which keeps segment vertices fixed) could lift: 9,863 tets, 937
// under 10 degrees, min 0.34 degrees after 70 s of perturbation (Mesh_3: 0.14 degrees). Now
// T1.1 splits at a small-angle star at l_min,i (the first pair of vertices on the two curves
// lies farther from the apex, where the curves are farther apart), the terminator leaves such
// subsegments encroached below twice the terminator length while they are Delaunay edges,
// and facets there that fail only the facet angle are left.
TEST(ThesisSharedModels, PartStepTangentCurvesDoNotCascadeIntoSlivers) {
  // The sweep's sharp-tet4 case (default sizes, sliver removal on). The time limit is far
  // above today's few seconds; the cascade took 75 s here.
  const SharedModelRun run = meshSharedModel("part.step", "part", {{"limits", {{"time_limit", 60}}}});
  const double brepVolume = run.brep_volume;
  const JobResult& r = run.result;
  const TetMesh& m = r.mesh;
  const json& thesis = r.report.at("thesis");
  const json& quality = r.report.at("quality");

  // Subsegments the terminator may leave encroached are still mesh edges.
  const json& check = thesis.at("final_check");
  EXPECT_EQ(check.at("subsegments_not_edges").get<int>(), 0);
  EXPECT_EQ(check.at("restricted_facets_off_boundary").get<int>(), 0);
  expectConforming(m);
  const double meshed = test::volumePerMaterial(m).at(1);
  EXPECT_NEAR(meshed, brepVolume, 0.01 * brepVolume);

  // Before: 9,863 tets, 937 under 10 degrees, min 0.34. Now 6,299, 33 and 0.27 (a sliver
  // across a curved face, with two faces on the boundary, that the improvement stage keeps).
  EXPECT_LT(m.tets.size(), 7000u);
  EXPECT_LT(quality.at("min_dihedral_histogram_10deg").at(0).get<int>(), 150);
  EXPECT_GT(quality.at("min_dihedral_deg").get<double>(), 0.2);
  // Every constrained subsegment is an edge of the final mesh (after sliver removal too).
  std::set<std::pair<int64_t, int64_t>> tetEdges;
  for (const auto& t : m.tets)
    for (const auto& e : test::kTetEdges) tetEdges.insert(std::minmax(t[e[0]], t[e[1]]));
  for (const auto& e : m.feature_edges) EXPECT_TRUE(tetEdges.count(std::minmax(e[0], e[1]))) << e[0] << "-" << e[1];
  std::cout << "[figures] part.step thesis sharp tet4: " << m.tets.size() << " tets, min dihedral "
            << quality.at("min_dihedral_deg") << ", under 10 degrees "
            << quality.at("min_dihedral_histogram_10deg").at(0) << ", slivers left "
            << thesis.at("slivers_left_total").get<int64_t>() << ", volume " << meshed << " vs B-rep "
            << brepVolume << "\n";
}

// Kurbelwelle.stp has two arcs of radius 9.5 on planes 0.2 mm apart (y = -5.085 and -5.285,
// a narrow cylindrical band). At the default size their chords came within the crossing
// split's reach (twice the sampling sagitta) at more than a degree, so both were split at a
// point between the planes, on neither curve; two subsegments there lay outside the solid and
// the job ended in "internal error: 2 of 1100 feature edges ... are no edge of any
// tetrahedron". Exact curves that never meet are no longer split.
TEST(ThesisSharedModels, KurbelwelleArcsCloseToEachOtherAreNotSplitAtAFalseCrossing) {
  const std::string file = test::cadDir() + "/Kurbelwelle.stp";
  const SharedModelRun run = meshSharedModel("Kurbelwelle.stp", "Kurbelwelle", {{"limits", {{"time_limit", 120}}}});
  const TetMesh& m = run.result.mesh;
  expectConforming(m);
  EXPECT_EQ(test::featureEdgesNotTetEdges(m), 0);
  EXPECT_GT(m.feature_edges.size(), 500u);
  // Every feature vertex lies on a B-rep edge of the part (the false crossing put one 0.1 mm
  // off both arcs): measured edge by edge, among the edges whose box holds the vertex.
  const double tolerance = 1e-6 * run.result.report.at("bbox_diagonal").get<double>();
  const auto loaded = BrepSolid::loadFile(file, "Kurbelwelle", BrepSolid::Grouping::Separate);
  std::vector<std::pair<TopoDS_Edge, Bnd_Box>> edges;
  for (TopExp_Explorer e(loaded.solids.at(0)->shape(), TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
    if (BRep_Tool::Degenerated(edge)) continue;
    Bnd_Box box;
    BRepBndLib::Add(edge, box);
    box.Enlarge(10 * tolerance);
    edges.push_back({edge, box});
  }
  std::set<int64_t> featureVertices;
  for (const auto& e : m.feature_edges) featureVertices.insert({e[0], e[1]});
  int64_t offEveryEdge = 0;
  for (int64_t v : featureVertices) {
    const Point3& p = m.points[v];
    const gp_Pnt point(p[0], p[1], p[2]);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& [edge, box] : edges) {
      if (box.IsOut(point)) continue;
      BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(point).Vertex(), edge);
      if (dist.IsDone()) nearest = std::min(nearest, dist.Value());
    }
    if (!(nearest <= tolerance)) {
      ++offEveryEdge;
      ADD_FAILURE() << "feature vertex " << v << " at (" << p[0] << ", " << p[1] << ", " << p[2] << ") is " << nearest
                    << " from the nearest B-rep edge";
    }
  }
  EXPECT_EQ(offEveryEdge, 0);
  // The volume check is the sizing field's matter (issue 16): here only that it is the part.
  EXPECT_NEAR(test::volumePerMaterial(m).at(1), run.brep_volume, 0.05 * run.brep_volume);
}

// screw.step at the default fineness: its 45-degree chamfer came out of the refinement with
// three flat tets (down to 1.2e-13 degrees) each with three faces on the boundary, the surface
// folded over itself there; flip, smoothing and the flat caps could not take them. The
// improvement stage now takes such folds out (their fourth face becomes the boundary), and
// reaches issue 15's 15 degrees everywhere (the screw's smallest input angle is 45 degrees):
// 12.0 degrees while new tets could be no larger than the ones they replaced, 20.0 with
// multi-face removal and new tets within the job's cell size and radius-edge ratio.
TEST(ThesisSharedModels, ScrewChamferFoldsGoAtTheDefaultFineness) {
  const SharedModelRun run = meshSharedModel("screw.step", "screw", {{"criteria", {{"fineness", "moderate"}}}});
  const TetMesh& m = run.result.mesh;
  const json& improve = run.result.report.at("improve");
  expectConforming(m);
  EXPECT_EQ(test::featureEdgesNotTetEdges(m), 0);
  EXPECT_GE(improve.at("flat_caps").at("folds_removed").get<int>(), 1);
  EXPECT_GT(run.result.report.at("quality").at("min_dihedral_deg").get<double>(), 15);
  // Taking the folds out moved no volume worth the name; the stage as a whole, its bound.
  EXPECT_LE(improve.at("flat_caps").at("largest_volume_change").get<double>(), 1e-9);
  EXPECT_LE(improve.at("curved_moves_largest_volume_share").get<double>(), 1e-5 * (1 + 1e-9));
  expectBoundaryNodesOnTheCad(run, "screw.step");
}

// screw.step at issue 15's size (cell and facet size diagonal / 25, facet distance diagonal /
// 1000, under the moderate fineness' field): where its slot meets the 45-degree chamfer,
// facets with a corner on the slot's bottom and one on the chamfer cone spanned the wedge
// between them, the wedge's tip under them was left out of the mesh, and a flat tet at that
// notch's rim joined two fans of tets at one vertex (2.4e-13 degrees; no improvement may take
// it: the part would be pinched there). Such facets are refined now
// (FacetAcrossSharpEdgeCriterion) and no tet is under 15 degrees.
TEST(ThesisSharedModels, ScrewSlotMeetsItsChamferWithoutAFoldAtIssue15Size) {
  const double diagonal = 103.10346540646871;
  const json size = {{"cell_size", diagonal / 25}, {"facet_size", diagonal / 25}, {"facet_distance", diagonal / 1000}};
  const SharedModelRun run =
      meshSharedModel("screw.step", "screw", {{"criteria", {{"fineness", "moderate"}, {"default", size}}}});
  const json& report = run.result.report;
  const TetMesh& m = run.result.mesh;
  ASSERT_NEAR(report.at("bbox_diagonal").get<double>(), diagonal, 1e-6 * diagonal);
  expectConforming(m);
  EXPECT_EQ(test::featureEdgesNotTetEdges(m), 0);
  int dihedrals45 = 0;
  for (const json& a : report.at("small_input_angles"))
    dihedrals45 += a.at("kind") == "dihedral" && std::abs(a.at("angle_deg").get<double>() - 45) < 1e-6;
  EXPECT_EQ(dihedrals45, 3) << "the chamfer's three arcs along the slot";
  for (const json& e : report.at("thesis").at("elements_left"))
    EXPECT_EQ(e.at("reason").get<std::string>().find("spans the wedge"), std::string::npos) << e.dump();
  double smallest = 180;
  for (const auto& tet : m.tets) smallest = std::min(smallest, smallestDihedral(m.points, tet));
  EXPECT_GE(smallest, 15);
  expectBoundaryNodesOnTheCad(run, "screw.step");
}

// Kurbelwelle.stp at the default fineness: its worst tets after flips and smoothing had a short
// edge whose ends could not move apart (0.026 degrees, 12 / 26 / 64 tets under 5 / 10 / 15);
// edge collapse takes such an end out (0.82 degrees, 4 / 13 / 27), multi-face removal and new
// tets within the job's criteria rather than the old tets' sizes lift the rest (3.7 degrees,
// 1 / 6 / 9; the one under 5 at a 42-degree input angle); curves sampled at their local size
// instead of their smallest and cells at twice the curvature's surface sizes leave none under
// 15 (15.5 degrees); the curved-move bound on the net volume change rather than on the sum of
// the changes' sizes lets the stage reach its 20-degree goal. What it keeps: every feature edge
// a mesh edge, every boundary node on the part, the volume within the curved-move bound.
TEST(ThesisSharedModels, KurbelwelleShortEdgesCollapseAtTheDefaultFineness) {
  const SharedModelRun run =
      meshSharedModel("Kurbelwelle.stp", "Kurbelwelle", {{"criteria", {{"fineness", "moderate"}}}});
  const TetMesh& m = run.result.mesh;
  const json& improve = run.result.report.at("improve");
  expectConforming(m);
  EXPECT_EQ(test::featureEdgesNotTetEdges(m), 0);
  EXPECT_GE(improve.at("operations").at("edge_collapses").get<int>(), 10);
  EXPECT_EQ(improve.at("tets_under_15_deg").get<int>(), 0);
  // Issue 15's moonshot, 20 degrees, is the stage's goal (15.5 with the bound on the sum).
  EXPECT_GE(improve.at("min_dihedral_after_deg").get<double>(), 19.5);
  // The stage moves the volume by at most its two curved bounds, for moves and collapses and for
  // curved caps (tet4 chords are 0.7 % short of the part with or without it).
  EXPECT_LE(improve.at("curved_moves_largest_volume_share").get<double>(), 1e-5 * (1 + 1e-9));
  const SharedModelRun unimproved = meshSharedModel(
      "Kurbelwelle.stp", "Kurbelwelle", {{"criteria", {{"fineness", "moderate"}}}, {"optimize", {{"improve", false}}}});
  const double before = test::volumePerMaterial(unimproved.result.mesh).at(1);
  EXPECT_NEAR(test::volumePerMaterial(m).at(1), before, 2 * 1e-5 * before);
  EXPECT_NEAR(before, run.brep_volume, 0.01 * run.brep_volume);
  // No vertex left without a tet after the renumbering, and every boundary node on the part.
  std::vector<char> used(m.points.size(), 0);
  for (const auto& t : m.tets)
    for (int64_t v : t) used[v] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
  expectBoundaryNodesOnTheCad(run, "Kurbelwelle.stp");
}

// Schenkel.stp at the default fineness has faces 0.061 mm wide beside 1.4 mm ones: their short
// edges are split in two or three (at most half their length) and the refinement leaves tets of
// 0.2 mm edges on those 0.02 - 0.03 mm subsegments, whose corners cannot move. Flips, collapses
// and smoothing leave tets under 10 degrees there; new interior vertices beside the short
// subsegments lift some of them. The insertion passes come after the others, so they start
// from where those stopped and only add.
TEST(ThesisSharedModels, SchenkelNarrowFacesGetNewVerticesAtTheDefaultFineness) {
  const SharedModelRun run = meshSharedModel("Schenkel.stp", "Schenkel", {{"criteria", {{"fineness", "moderate"}}}});
  const TetMesh& m = run.result.mesh;
  const json& improve = run.result.report.at("improve");
  const json& before = improve.at("before_insertion");
  std::cout << "[ figures  ] Schenkel.stp default: " << improve.at("operations").at("vertex_insertions")
            << " insertions, min dihedral " << before.at("min_dihedral_deg") << " -> "
            << improve.at("min_dihedral_after_deg") << ", under 5/10/15 " << before.at("under_5_deg") << "/"
            << before.at("under_10_deg") << "/" << before.at("under_15_deg") << " -> " << improve.at("tets_under_5_deg")
            << "/" << improve.at("tets_under_10_deg") << "/" << improve.at("tets_under_15_deg") << "\n";
  expectConforming(m);
  EXPECT_EQ(test::featureEdgesNotTetEdges(m), 0);
  EXPECT_GT(improve.at("operations").at("vertex_insertions").get<int>(), 0);
  EXPECT_LT(improve.at("tets_under_15_deg").get<int>(), before.at("under_15_deg").get<int>());
  EXPECT_LE(improve.at("tets_under_10_deg").get<int>(), before.at("under_10_deg").get<int>());
  EXPECT_GE(improve.at("min_dihedral_after_deg").get<double>(), before.at("min_dihedral_deg").get<double>());
  EXPECT_EQ(improve.at("tets_under_5_deg").get<int>(), 0);
  // Inserted vertices (dimension 3) are interior: on no boundary triangle. The volume is the
  // CAD's to the tet4 chords.
  int64_t interiorOnBoundary = 0;
  for (const BoundaryTriangle& b : m.boundary)
    for (int64_t v : b.v) interiorOnBoundary += m.vertex_dimension.at(v) == 3;
  EXPECT_EQ(interiorOnBoundary, 0);
  EXPECT_NEAR(test::volumePerMaterial(m).at(1), run.brep_volume, 0.01 * run.brep_volume);
}

// part.step at the default fineness: a line tangent to an arc at six corners (0 - 0.15 degree
// curve angles) left the first vertices of the two curves a hundredth of a millimetre apart,
// each on its own curve, which no operation may join: all 78 tets under 15 degrees were there.
// Near those corners the arc now stands for both (features/TangentCusps.h): the six corners are
// reported, the curves part at over 15 degrees, and no tet is under 15 degrees (16.8 measured).
TEST(ThesisSharedModels, PartStepTangentCornersAreMergedAndNoTetIsUnder15DegreesAtTheDefaultFineness) {
  const SharedModelRun run = meshSharedModel("part.step", "part", {{"criteria", {{"fineness", "moderate"}}}});
  const json& report = run.result.report;
  expectConforming(run.result.mesh);
  EXPECT_EQ(test::featureEdgesNotTetEdges(run.result.mesh), 0);
  const json& cusps = report.at("features").at("tangent_cusps");
  EXPECT_EQ(cusps.size(), 6u) << cusps.dump();
  for (const json& a : report.at("small_input_angles")) EXPECT_GT(a.at("angle_deg").get<double>(), 15) << a.dump();
  double smallest = 180;
  for (const auto& tet : run.result.mesh.tets) smallest = std::min(smallest, smallestDihedral(run.result.mesh.points, tet));
  EXPECT_GE(smallest, 15);
  EXPECT_EQ(report.at("improve").at("tets_under_15_deg").get<int>(), 0);
  expectBoundaryNodesOnTheCad(run, "part.step");
}

// screw.step with engine cgal at the default size: four protected edges were edges of the
// regular triangulation whose cells all lay outside the complex (circumcentres outside the
// screw), so the job ended in "internal error: 4 of 340 feature edges ... are no edge of any
// tetrahedron". The cells around such an edge whose barycentre is in the screw are now taken.
TEST(Mesh3SharedModels, ScrewKeepsEveryProtectedEdgeAtTheDefaultSize) {
  const SharedModelRun run = meshSharedModel("screw.step", "screw", {{"engine", "cgal"}, {"limits", {{"time_limit", 120}}}});
  const TetMesh& m = run.result.mesh;
  expectConforming(m);
  EXPECT_GT(m.feature_edges.size(), 300u);
  EXPECT_EQ(test::featureEdgesNotTetEdges(m), 0);
  // At this size the screw's thread is coarser than its elements: the self-check says so
  // (volume and pieces) rather than the mesh looking right.
  const double meshed = test::volumePerMaterial(m).at(1);
  EXPECT_NEAR(meshed, run.brep_volume, 0.10 * run.brep_volume);
  if (std::abs(meshed - run.brep_volume) > 0.01 * run.brep_volume)
    EXPECT_FALSE(run.result.report.at("self_check").at("problems").empty());
}

}  // namespace
}  // namespace oraclemesh
