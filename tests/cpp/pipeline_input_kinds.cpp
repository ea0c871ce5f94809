// Input kinds through the whole pipeline (issue 4): a multi-solid B-rep with one material per
// solid and a cut, checked against OpenCASCADE Booleans of the same priority composition, and
// an STL of the demo pin against the B-rep pin.
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Ax2.hxx>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "Error.h"
#include "job/Pipeline.h"
#include "mesh_checks.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

using test::compoundOf;

using test::brepText;
using test::volumeOf;

TopoDS_Shape cut(const TopoDS_Shape& a, const TopoDS_Shape& b) { return BRepAlgoAPI_Cut(a, b).Shape(); }

TEST(InputKinds, ThreePartAssemblyWithCutMatchesBooleanComposition) {
  // One file with three overlapping parts in priority order (a cylinder through two boxes that
  // overlap each other), one material per solid, and a cut box across all three.
  const TopoDS_Shape a = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20, 15, -5), gp_Dir(0, 0, 1)), 6, 30).Shape();
  const TopoDS_Shape b = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 40, 30, 10).Shape();
  const TopoDS_Shape c = BRepPrimAPI_MakeBox(gp_Pnt(25, 5, 5), 30, 20, 15).Shape();
  const TopoDS_Shape cutBox = BRepPrimAPI_MakeBox(gp_Pnt(15, -5, 15), 45, 17, 15).Shape();
  BRep_Builder builder;
  TopoDS_Compound parts;
  builder.MakeCompound(parts);
  for (const TopoDS_Shape& s : {a, b, c}) builder.Add(parts, s);

  const nlohmann::json job = {
      {"inputs",
       {{{"name", "corner"}, {"brep", brepText(cutBox)}, {"role", "cut"}},
        {{"name", "assembly"}, {"brep", brepText(parts)}, {"materials", {1, 2, 3}}}}},
      {"criteria", {{"default", {{"cell_size", 4}, {"facet_size", 3}, {"facet_distance", 0.1}, {"edge_size", 2}}}}},
      {"element_order", 2},
      {"optimize", false}};
  const JobResult result = runJob(JobSpec::fromJson(job, ""), RunControl());

  const std::map<int, double> expected = {{1, volumeOf(cut(a, cutBox))},
                                          {2, volumeOf(cut(cut(b, a), cutBox))},
                                          {3, volumeOf(cut(cut(cut(c, a), b), cutBox))}};
  const std::map<int, double> volumes = test::volumePerMaterial(result.mesh);
  ASSERT_EQ(volumes.size(), 3u);
  for (const auto& [material, v] : expected) {
    // Planar faces and the straight junctions are met exactly by the snapped nodes; what is
    // left is the tet10 chord error on the cylinder (radius 6, facet_distance 0.1): 0.5 %.
    EXPECT_NEAR(volumes.at(material), v, 0.005 * v) << "material " << material;
    std::cout << "[figures] material " << material << ": tet10 volume " << volumes.at(material) << " vs Boolean " << v
              << " (" << 100 * (volumes.at(material) / v - 1) << " %)\n";
  }
  const nlohmann::json& inputs = result.report["inputs"];
  ASSERT_EQ(inputs.size(), 4u);
  EXPECT_EQ(inputs[0]["name"], "corner");
  for (int i = 1; i <= 3; ++i) {
    EXPECT_EQ(inputs[i]["name"], "assembly#" + std::to_string(i));
    EXPECT_EQ(inputs[i]["input"], "assembly");
    EXPECT_EQ(inputs[i]["kind"], "B-rep solid");
    EXPECT_EQ(inputs[i]["material"], i);
  }
}

TEST(InputKinds, StlPinMeshesWithTheVolumeOfTheBrepPin) {
  // The demo's pin, tessellated finely (chord error 1e-3 mm on radius 5: the polygon's volume
  // is 0.04 % under the cylinder's), meshed from the STL and from the B-rep.
  const TopoDS_Shape pin = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(30, 30, -10), gp_Dir(0, 0, 1)), 5, 30).Shape();
  BRepMesh_IncrementalMesh(pin, 1e-3, Standard_False, 0.05, Standard_False);
  const std::string stl = (std::filesystem::temp_directory_path() / "oraclemesh_demo_pin.stl").string();
  test::writeTessellationStl(pin, stl);

  auto volumeFrom = [](const nlohmann::json& input) {
    const nlohmann::json job = {
        {"inputs", {input}},
        {"criteria", {{"default", {{"cell_size", 2}, {"facet_size", 2}, {"facet_distance", 0.05}}}}},
        {"element_order", 2},
        {"optimize", false}};
    const JobResult r = runJob(JobSpec::fromJson(job, ""), RunControl());
    EXPECT_EQ(r.report["inputs"].size(), 1u);
    return std::pair{test::volumePerMaterial(r.mesh).at(1), r.report["inputs"][0]["kind"].get<std::string>()};
  };
  const auto [fromStl, stlKind] = volumeFrom({{"name", "pin"}, {"file", stl}, {"material", 1}});
  const auto [fromBrep, brepKind] = volumeFrom({{"name", "pin"}, {"brep", brepText(pin)}, {"material", 1}});
  std::remove(stl.c_str());
  EXPECT_EQ(stlKind, "triangle surface");
  EXPECT_EQ(brepKind, "B-rep solid");
  const double cylinder = volumeOf(pin);
  EXPECT_NEAR(fromStl, fromBrep, 0.005 * fromBrep);
  EXPECT_NEAR(fromBrep, cylinder, 0.005 * cylinder);
  std::cout << "[figures] pin tet10 volume: from STL " << fromStl << ", from B-rep " << fromBrep << ", cylinder "
            << cylinder << " (STL vs B-rep " << 100 * (fromStl / fromBrep - 1) << " %)\n";
}

std::string jobError(const nlohmann::json& input) {
  try {
    runJob(JobSpec::fromJson({{"inputs", {input}}}, ""), RunControl());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(InputKinds, PerSolidKeysAreCheckedAgainstTheFile) {
  const std::string twoBoxes = brepText(compoundOf({BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 1, 1, 1).Shape(),
                                                    BRepPrimAPI_MakeBox(gp_Pnt(2, 0, 0), 1, 1, 1).Shape()}));
  const std::pair<nlohmann::json, std::string> cases[] = {
      {{{"name", "pair"}, {"brep", twoBoxes}, {"materials", {1}}},
       "input 'pair' has 2 solids but 'materials' lists 1: give one material per solid, in file order"},
      {{{"name", "pair"}, {"brep", twoBoxes}, {"material", 1}, {"materials", {1, 2}}}, "both 'material' and 'materials'"},
      {{{"name", "pair"}, {"brep", twoBoxes}, {"solids", "apart"}}, "'solids' must be \"separate\""},
      {{{"name", "pair"}, {"brep", twoBoxes}, {"solids", "together"}, {"materials", {1, 2}}},
       "belongs to STEP, IGES or BREP inputs with \"solids\": \"separate\""},
      {{{"name", "pair"}, {"brep", twoBoxes}, {"materials", {1, 0}}}, "positive integer ids"},
  };
  for (const auto& [input, expected] : cases) {
    const std::string message = jobError(input);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST(InputKinds, OpenShellBesideASolidIsAWarningInTheReport) {
  BRepBuilderAPI_Sewing sewing;
  int face = 0;
  for (TopExp_Explorer ex(BRepPrimAPI_MakeBox(gp_Pnt(20, 0, 0), 10, 10, 10).Shape(), TopAbs_FACE); ex.More(); ex.Next())
    if (face++ != 0) sewing.Add(ex.Current());  // a box without its lid
  sewing.Perform();
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10, 10, 10).Shape();
  const nlohmann::json job = {
      {"inputs", {{{"name", "asm"}, {"brep", brepText(compoundOf({box, sewing.SewedShape()}))}, {"material", 1}}}},
      {"criteria", {{"default", {{"cell_size", 5}}}}},
      {"element_order", 1},
      {"optimize", false}};
  const JobResult result = runJob(JobSpec::fromJson(job, ""), RunControl());
  EXPECT_NEAR(test::volumePerMaterial(result.mesh).at(1), 1000, 1e-9 * 1000);
  ASSERT_EQ(result.report["inputs"].size(), 1u);
  EXPECT_EQ(result.report["inputs"][0]["name"], "asm");
  bool warned = false;
  for (const auto& w : result.report["warnings"])
    warned |= w.get<std::string>().find("input 'asm': open shell (item 2 of 2, 5 faces, 4 free edges") == 0;
  EXPECT_TRUE(warned) << result.report["warnings"].dump();
}

}  // namespace
}  // namespace oraclemesh
