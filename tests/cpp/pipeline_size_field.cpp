// Sizes from the geometry (issue 16 item 1): a job that gives no size and asks for the fineness
// "moderate" gets the sizing field, so a small round part in a large model keeps its volume and
// its roundness, a thin wall gets layers through it, and a wall too thin for the vertex limit
// is refused up front.
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>
#include <gp_Pnt.hxx>

#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <set>

#include "Error.h"
#include "domain/HierarchicalOracle.h"
#include "job/InputLoading.h"
#include "job/Pipeline.h"
#include "job/ResolvedCriteria.h"
#include "sizing/Fineness.h"
#include "input_errors.h"
#include "mesh_checks.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

using nlohmann::json;

// A pin of radius 3 through a 200 mm block: the default cap (diagonal / 15, 19 mm) is six
// times the pin's radius, so without sizes from its curvature the pin is a few tets wide.
json pinInBlockJob() {
  const TopoDS_Shape pin = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(100, 100, -10), gp_Dir(0, 0, 1)), 3, 60).Shape();
  const TopoDS_Shape block = BRepPrimAPI_MakeBox(200, 200, 40).Shape();
  return {{"inputs",
           {{{"name", "pin"}, {"brep", test::brepText(pin)}, {"material", 1}},
            {{"name", "block"}, {"brep", test::brepText(block)}, {"material", 2}}}},
          {"features", {{"sharp_angle_deg", 30}}},
          {"element_order", 2},  // mid nodes on the CAD: the volume is the pin's, not its facets'
          {"criteria", {{"fineness", "moderate"}}},
          {"seed", 0}};
}

// Distinct directions from the axis of the corner vertices on the pin's top rim (z = 50).
int rimSegments(const TetMesh& mesh) {
  std::set<int64_t> corners;
  for (const auto& t : mesh.tets) corners.insert(t.begin(), t.end());
  std::set<long> angles;
  for (int64_t v : corners) {
    const Point3& p = mesh.points[v];
    const double r = std::hypot(p[0] - 100, p[1] - 100);
    if (std::abs(p[2] - 50) < 1e-6 && std::abs(r - 3) < 1e-3)
      angles.insert(std::lround(std::atan2(p[1] - 100, p[0] - 100) * 1e4));
  }
  return static_cast<int>(angles.size());
}

TEST(SizeFieldModerate, ASmallPinInALargeBlockKeepsItsVolumeAndTwelveSegmentsAround) {
  const JobResult r = runJob(JobSpec::fromJson(pinInBlockJob(), ""), RunControl());
  const double pinVolume = M_PI * 9 * 60;
  const double meshed = test::volumePerMaterial(r.mesh).at(1);
  std::cout << "[ figures  ] pin " << meshed << " vs " << pinVolume << ", rim nodes " << rimSegments(r.mesh)
            << ", tets " << r.mesh.tets.size() << "\n";
  EXPECT_NEAR(meshed, pinVolume, 0.005 * pinVolume);
  EXPECT_GE(rimSegments(r.mesh), 12);
  EXPECT_EQ(r.report.at("criteria").at("fineness"), "moderate");
  EXPECT_GT(r.report.at("criteria").at("size_field").at("samples").at("curvature").get<int>(), 0);

  // The same job without the field: the pin is what the cap gives (the test shows the field
  // is what keeps it round).
  json off = pinInBlockJob();
  off["criteria"] = {{"fineness", "off"}};
  off["checks"] = "warn";  // the cap alone loses the pin's volume: kept, to be compared
  const JobResult coarse = runJob(JobSpec::fromJson(off, ""), RunControl());
  std::cout << "[ figures  ] without the field: rim segments " << rimSegments(coarse.mesh) << "\n";
  EXPECT_LT(rimSegments(coarse.mesh), 12);
  EXPECT_FALSE(coarse.report.at("criteria").contains("size_field"));
}

// The sizes a job's criteria give at a point, as the pipeline attaches them (no contact
// tolerance: single inputs).
CriteriaTable attachedCriteria(const json& job) {
  const JobSpec spec = JobSpec::fromJson(job, "");
  RunControl control;
  const HierarchicalOracle oracle(loadInputs(spec, control).entries);
  CriteriaTable table = resolveCriteria(spec, oracle.diagonal());
  attachSizeField(table, spec, oracle, 0, control);
  return table;
}

// Cells may be twice what the curvature asks of the pin's faces (surface Delaunay balls;
// cells that small filled curved parts with 2.7 - 3.0 tets per boundary triangle where Gmsh
// makes 1.67), but no larger than a wall's thickness asks: the plate's cells stay at a third
// of its thickness, its layers through it as they were.
TEST(SizeFieldModerate, CellsTakeTwiceTheCurvatureSizesButAWallsThicknessAsItIs) {
  const CriteriaTable pin = attachedCriteria(pinInBlockJob());
  ASSERT_TRUE(pin.field && pin.cell_field);
  const Point3 onPin{103, 100, 20};  // on the pin's side, in the block
  const double surface = pin.field->at(onPin), cell = pin.cellSizeAt(1, onPin);
  std::cout << "[ figures  ] pin: facet size " << pin.facetSizeAt(1, onPin) << ", cell size " << cell << "\n";
  EXPECT_NEAR(pin.facetSizeAt(1, onPin), surface, 1e-12 * surface);
  // 12 segments around a radius of 3: 0.3 of it, and up to a third more between the samples
  // (grading, thinning).
  EXPECT_GE(surface, 0.3 * 3 * (1 - 1e-9));
  EXPECT_LE(surface, 0.4 * 3);
  EXPECT_NEAR(cell / surface, kCellSizePerSurfaceSize, 0.1 * kCellSizePerSurfaceSize);

  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(100, 100, 1).Shape();
  const CriteriaTable wall = attachedCriteria(
      {{"inputs", {{{"name", "plate"}, {"brep", test::brepText(plate)}, {"material", 1}}}}, {"element_order", 1}});
  const Point3 inWall{50, 50, 0};  // on its bottom face
  std::cout << "[ figures  ] plate: facet size " << wall.facetSizeAt(1, inWall) << ", cell size "
            << wall.cellSizeAt(1, inWall) << "\n";
  EXPECT_LE(wall.cellSizeAt(1, inWall), 0.42);  // a third of the thickness, and up to 0.2 of it more between samples
  EXPECT_NEAR(wall.cellSizeAt(1, inWall), wall.facetSizeAt(1, inWall), 1e-12);
}

// Issue 16's plate, 100 x 100 x 1, with no size and no fineness in the job: three sizes through
// the wall ("moderate"). A tetrahedron with corners on both faces would span it in one layer.
TEST(SizeFieldModerate, AThinPlateGetsMoreThanOneLayerThroughItsThicknessAtTheDefault) {
  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(100, 100, 1).Shape();
  const json job = {{"inputs", {{{"name", "plate"}, {"brep", test::brepText(plate)}, {"material", 1}}}},
                    {"features", {{"sharp_angle_deg", 30}}},
                    {"element_order", 1}};
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  int64_t spanning = 0;
  for (const auto& t : r.mesh.tets) {
    bool bottom = false, top = false;
    for (int64_t v : t) {
      bottom = bottom || std::abs(r.mesh.points[v][2]) < 1e-9;
      top = top || std::abs(r.mesh.points[v][2] - 1) < 1e-9;
    }
    spanning += bottom && top;
  }
  std::cout << "[ figures  ] plate: " << r.mesh.tets.size() << " tets, " << spanning << " spanning the wall\n";
  EXPECT_EQ(r.report.at("criteria").at("fineness"), "moderate");
  EXPECT_EQ(spanning, 0);
  EXPECT_NEAR(test::volumePerMaterial(r.mesh).at(1), 1e4, 1e4 * 1e-6);
}

// 100 x 100 x 0.1 and x 0.01 at the default: three sizes through the wall would need tens of
// millions or billions of vertices; the job stops before meshing and says so.
TEST(SizeFieldModerate, AWallTooThinForTheVertexLimitIsRefusedUpFrontAtTheDefault) {
  for (const double thickness : {0.1, 0.01}) {
    const TopoDS_Shape plate = BRepPrimAPI_MakeBox(100, 100, thickness).Shape();
    const json job = {{"inputs", {{{"name", "foil"}, {"brep", test::brepText(plate)}, {"material", 1}}}}};
    try {
      runJob(JobSpec::fromJson(job, ""), RunControl());
      ADD_FAILURE() << "a " << thickness << " mm foil at the default fineness was meshed";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("input 'foil'"), std::string::npos) << message;
      EXPECT_NE(message.find("limits.max_vertices"), std::string::npos) << message;
      EXPECT_NE(message.find("from thickness"), std::string::npos) << message;
      EXPECT_NE(message.find("criteria.fineness moderate"), std::string::npos) << message;
    }
  }
}

// A box with a cell size far too small for the vertex limit: the message blames the size given,
// not a curvature the box does not have (it said "0.05 at (0, 0, 0), from curvature").
TEST(SizeFieldModerate, SizesGivenTooSmallForTheVertexLimitAreNamedAsGiven) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(20, 10, 10).Shape();
  const json job = {{"inputs", {{{"name", "GoodBox"}, {"brep", test::brepText(box)}, {"material", 1}}}},
                    {"criteria", {{"default", {{"cell_size", 0.05}}}}},
                    {"limits", {{"max_vertices", 1000}}}};
  const std::string message = test::inputErrorOf([&] { runJob(JobSpec::fromJson(job, ""), RunControl()); });
  for (const char* part : {"the sizes given (cell_size 0.05 on input 'GoodBox')", "limits.max_vertices = 1000",
                           "raise cell_size and facet_size"})
    EXPECT_NE(message.find(part), std::string::npos) << part << "\n" << message;
  EXPECT_EQ(message.find("curvature"), std::string::npos) << message;
}

TEST(SizeFieldModerate, IsTheDefaultUnderTheGivenSizesAndOffTurnsItOff) {
  json job = pinInBlockJob();
  job["criteria"] = {{"default", {{"cell_size", 20}}}};
  job["checks"] = "warn";  // at "off" the pin comes out short; the fields are what is checked
  const JobResult unset = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_EQ(unset.report.at("criteria").at("fineness"), "moderate");
  EXPECT_EQ(unset.report.at("criteria").at("size_field").at("segments_per_circle"), 12);
  EXPECT_LE(unset.report.at("criteria").at("size_field").at("largest").get<double>(), 20);
  job["criteria"]["fineness"] = "off";
  const JobResult off = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_EQ(off.report.at("criteria").at("fineness"), "off");
  EXPECT_FALSE(off.report.at("criteria").contains("size_field"));
  EXPECT_LT(off.mesh.tets.size(), unset.mesh.tets.size());
  job["criteria"]["fineness"] = "coarse";
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_EQ(r.report.at("criteria").at("size_field").at("segments_per_circle"), 8);
  job["criteria"]["fineness"] = "medium";
  try {
    JobSpec::fromJson(job, "");
    FAIL() << "an unknown fineness was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("criteria.fineness = \"medium\""), std::string::npos) << e.what();
  }
}

// Two 10 mm cubes one above the other, `gap` apart, at the default sizes (cap: diagonal / 15,
// 1.4 mm) and the given fineness; tet4 without sliver removal, for speed.
json twoCubesJob(double gap, const std::string& fineness) {
  const TopoDS_Shape lower = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10, 10, 10).Shape();
  const TopoDS_Shape upper = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 10 + gap), 10, 10, 10).Shape();
  const json job = {{"inputs",
                     {{{"name", "lower"}, {"brep", test::brepText(lower)}, {"material", 1}},
                      {{"name", "upper"}, {"brep", test::brepText(upper)}, {"material", 2}}}},
                    {"criteria", {{"fineness", fineness}}},
                    {"element_order", 1},
                    {"optimize", {{"perturb", false}, {"exude", false}}},
                    {"seed", 0}};
  return job;
}

JobResult twoCubes(double gap, const std::string& fineness) {
  return runJob(JobSpec::fromJson(twoCubesJob(gap, fineness), ""), RunControl());
}

// Issue 16 item 3: a gap between parts is resolved by the sizes at every preset (without the
// field, cells of 1.4 mm reach across 0.5 mm and bond the cubes: SelfCheck's test), and parts
// 1e-9 apart touch: bonded over their whole 100 mm^2 face. very_fine is left out: it makes
// over half a million tets here, minutes for the test suite.
TEST(SizeFieldGaps, CubesHalfAMillimetreApartStayApartAtEveryPresetUpToFine) {
  for (const FinenessPreset& preset : kFinenessPresets) {
    if (std::string(preset.name) == "very_fine") continue;
    const JobResult r = twoCubes(0.5, preset.name);
    const json& check = r.report.at("self_check");
    std::cout << "[ figures  ] " << preset.name << ": " << r.mesh.tets.size() << " tets, gap samples "
              << r.report.at("criteria").at("gap_sizes").at("samples").at("gap") << "\n";
    EXPECT_TRUE(check.at("joined").empty()) << preset.name << ": " << check.dump(1);
    EXPECT_TRUE(r.report.at("interfaces").empty()) << preset.name << ": " << r.report.at("interfaces").dump(1);
    const auto volumes = test::volumePerMaterial(r.mesh);
    EXPECT_NEAR(volumes.at(1), 1000, 1e-6) << preset.name;
    EXPECT_NEAR(volumes.at(2), 1000, 1e-6) << preset.name;
  }
}

// Without a fineness ("off", the sizes constant) a gap gets sizes too: cells of 1.4 mm had
// bonded cubes 0.2 mm apart over 39 of their 100 mm^2.
TEST(SizeFieldGaps, CubesAFifthOfAMillimetreApartStayApartWithoutAFineness) {
  const JobResult r = twoCubes(0.2, "off");
  const json& gapSizes = r.report.at("criteria").at("gap_sizes");
  EXPECT_FALSE(r.report.at("criteria").contains("size_field"));
  ASSERT_EQ(gapSizes.at("gaps").size(), 1u) << gapSizes.dump(1);
  EXPECT_NEAR(gapSizes.at("gaps")[0].at("width").get<double>(), 0.2, 1e-9);
  EXPECT_GT(gapSizes.at("samples").at("gap").get<int>(), 0);
  EXPECT_NEAR(gapSizes.at("smallest").at("size").get<double>(),
              0.2 / gapSizes.at("sizes_per_gap").get<double>(), 1e-9);
  EXPECT_TRUE(r.report.at("self_check").at("joined").empty()) << r.report.at("self_check").dump(1);
  EXPECT_TRUE(r.report.at("interfaces").empty()) << r.report.at("interfaces").dump(1);
  const auto volumes = test::volumePerMaterial(r.mesh);
  EXPECT_NEAR(volumes.at(1), 1000, 1e-6);
  EXPECT_NEAR(volumes.at(2), 1000, 1e-6);
}

TEST(SizeFieldGaps, CubesWithinTheContactToleranceAreBonded) {
  const JobResult r = twoCubes(1e-9, "moderate");
  // The default: 1e-6 of the diagonal (BRep boxes carry 1e-7, BREP text declares nothing).
  EXPECT_EQ(r.report.at("contact_tolerance").at("from"), "diagonal");
  EXPECT_NEAR(r.report.at("contact_tolerance").at("value").get<double>(), 1e-6 * std::sqrt(100 + 100 + 400), 1e-9);
  EXPECT_TRUE(r.report.at("criteria").at("gap_sizes").at("gaps").empty());
  EXPECT_FALSE(r.report.at("criteria").at("gap_sizes").contains("samples"));
  EXPECT_TRUE(r.report.at("self_check").at("joined").empty()) << r.report.at("self_check").dump(1);
  ASSERT_EQ(r.report.at("interfaces").size(), 1u);
  EXPECT_NEAR(r.report.at("interfaces")[0].at("area").get<double>(), 100.0, 1e-6);
}

// The half-millimetre gap's pair and width are in the report; a contact_tolerance above the
// width makes the cubes touch: no gap sizes, and the self-check takes them as touching.
TEST(SizeFieldGaps, TheReportListsTheGapAndAWiderContactToleranceBondsIt) {
  const JobResult apart = twoCubes(0.5, "coarse");
  const json& gaps = apart.report.at("criteria").at("gap_sizes").at("gaps");
  ASSERT_EQ(gaps.size(), 1u) << gaps.dump(1);
  EXPECT_EQ(gaps[0].at("between"), json({"lower", "upper"}));
  EXPECT_NEAR(gaps[0].at("width").get<double>(), 0.5, 1e-9);

  json job = twoCubesJob(0.5, "coarse");
  job["contact_tolerance"] = 0.6;
  const JobResult bonded = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_EQ(bonded.report.at("contact_tolerance"), json({{"value", 0.6}, {"from", "job"}}));
  EXPECT_FALSE(bonded.report.at("criteria").at("gap_sizes").contains("samples"));
  EXPECT_TRUE(bonded.report.at("criteria").at("gap_sizes").at("gaps").empty());
  EXPECT_GE(bonded.report.at("self_check").at("contact_tolerance").get<double>(), 0.6);
  EXPECT_TRUE(bonded.report.at("self_check").at("joined").empty());

  // The uncertainty a STEP file declared, sent by the workbench for shapes that no longer
  // carry it, raises the automatic tolerance the same way; an explicit one still wins.
  job.erase("contact_tolerance");
  job["cad_uncertainty"] = 0.6;
  const JobResult declared = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_EQ(declared.report.at("contact_tolerance"), json({{"value", 0.6}, {"from", "cad_uncertainty (job)"}}));
  EXPECT_FALSE(declared.report.at("criteria").at("gap_sizes").contains("samples"));
  EXPECT_TRUE(declared.report.at("self_check").at("joined").empty());
  job["contact_tolerance"] = 0.01;
  const JobResult explicitWins = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_EQ(explicitWins.report.at("contact_tolerance"), json({{"value", 0.01}, {"from", "job"}}));
  EXPECT_EQ(explicitWins.report.at("criteria").at("gap_sizes").at("gaps").size(), 1u);
}

// Issue 16 item 3 / issue 19: a gap narrower than the terminator length of the caps. Cells of
// 20 mm (given: the field lowers the facet and edge sizes only) put that terminator at 10 / 32
// = 0.31 mm, as presse_asm.step's caps put it at 0.6 mm beside its 0.5 mm clearance; the 0.2
// mm gap asks for 0.2 / 3 on both faces ("moderate"). With one terminator for the whole mesh
// no vertex went in closer than 0.31 mm to another, and tets bridged the gap (48 mm^2 of
// interface, both volumes +0.8 %); at the gap the field's size sets it.
TEST(SizeFieldGaps, AGapNarrowerThanTheCapsTerminatorStaysOpen) {
  const double gap = 0.2;
  json job = twoCubesJob(gap, "moderate");
  job["criteria"]["default"] = {{"cell_size", 20}};
  job["contact_tolerance"] = 0.01;
  const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
  const TetMesh& mesh = r.mesh;
  int64_t spanning = 0;  // tets with corners on both sides of the gap's mid-plane
  std::map<int64_t, std::set<int>> materialsAt;
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    bool below = false, above = false;
    for (int64_t v : mesh.tets[t]) {
      below = below || mesh.points[v][2] < 10 + gap / 2;
      above = above || mesh.points[v][2] > 10 + gap / 2;
      materialsAt[v].insert(mesh.tet_materials[t]);
    }
    spanning += below && above;
  }
  int64_t shared = 0;
  for (const auto& [v, materials] : materialsAt) shared += materials.size() > 1;
  std::map<test::Face, std::vector<int>> owners;
  test::boundaryFaces(mesh, &owners);
  int64_t interfaceFaces = 0;
  for (const auto& [face, materials] : owners) interfaceFaces += materials.size() == 2 && materials[0] != materials[1];
  const auto volumes = test::volumePerMaterial(mesh);
  std::cout << "[ figures  ] " << mesh.tets.size() << " tets, " << spanning << " spanning the gap, " << shared
            << " shared vertices, " << interfaceFaces << " interface triangles, volumes " << volumes.at(1) << ", "
            << volumes.at(2) << ", thesis " << r.report.at("seconds").at("thesis") << " s\n";
  EXPECT_EQ(spanning, 0);
  EXPECT_EQ(shared, 0);
  EXPECT_EQ(interfaceFaces, 0);
  EXPECT_TRUE(r.report.at("interfaces").empty()) << r.report.at("interfaces").dump(1);
  EXPECT_TRUE(r.report.at("self_check").at("joined").empty()) << r.report.at("self_check").dump(1);
  EXPECT_NEAR(volumes.at(1), 1000, 5);
  EXPECT_NEAR(volumes.at(2), 1000, 5);
}

// A gap of 1e-3 mm at "moderate" asks for 3e-4 mm over 100 mm^2 on both sides, some 1e9
// surface vertices: refused before meshing, naming both parts, the width and both fixes.
TEST(SizeFieldGaps, AGapTooNarrowForTheVertexLimitNamesBothPartsAndTheFixes) {
  const std::string message = test::inputErrorOf([] { twoCubes(1e-3, "moderate"); });
  for (const char* part : {"the gap between inputs 'lower' and 'upper' is 0.001 wide at (",
                           "contact_tolerance above 0.001 (now ", ") to bond them",
                           "raise limits.max_vertices", "limits.max_vertices = 5000000"})
    EXPECT_NE(message.find(part), std::string::npos) << part << "\n" << message;
}

}  // namespace
}  // namespace oraclemesh
