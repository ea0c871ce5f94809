// The uncertainty a STEP file declares (UNCERTAINTY_MEASURE_WITH_UNIT) reaches the loaded
// input in model units, read in-process and through the helper process alike: the default
// contact tolerance starts from it (job/ContactTolerance).
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepTools.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>

#include <filesystem>
#include <fstream>
#include <string>

#include "Error.h"
#include "RunControl.h"
#include "domain/BrepSolid.h"
#include "domain/brep/ShapeFiles.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

// A 10 x 20 x 30 mm box written as STEP in `unit` ("MM" or "M") declaring `uncertainty` mm.
std::string boxStep(const std::string& unit, double uncertaintyMm) {
  STEPControl_Controller::Init();
  const std::string oldUnit = Interface_Static::CVal("write.step.unit");
  const int oldMode = Interface_Static::IVal("write.precision.mode");
  const double oldValue = Interface_Static::RVal("write.precision.val");
  Interface_Static::SetCVal("write.step.unit", unit.c_str());
  Interface_Static::SetIVal("write.precision.mode", 2);  // the user's value below
  Interface_Static::SetRVal("write.precision.val", uncertaintyMm);
  STEPControl_Writer writer;
  writer.Transfer(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), STEPControl_AsIs);
  const auto path = std::filesystem::temp_directory_path() / ("oraclemesh_uncertainty_" + unit + ".step");
  const bool written = writer.Write(path.string().c_str()) == IFSelect_RetDone;
  Interface_Static::SetCVal("write.step.unit", oldUnit.c_str());
  Interface_Static::SetIVal("write.precision.mode", oldMode);
  Interface_Static::SetRVal("write.precision.val", oldValue);
  return written ? path.string() : "";
}

TEST(StepUncertainty, TheDeclaredUncertaintyComesBackInModelUnits) {
  for (const char* unit : {"MM", "M"}) {
    const std::string path = boxStep(unit, 0.02);
    ASSERT_FALSE(path.empty()) << unit;
    const BrepSolid::Loaded here = BrepSolid::loadFile(path, "box", BrepSolid::Grouping::Separate);
    ASSERT_EQ(here.solids.size(), 1u);
    EXPECT_NEAR(here.solids[0]->volume(), 6000, 1e-6 * 6000) << unit;  // the file is read in mm
    EXPECT_NEAR(here.declared_uncertainty, 0.02, 1e-12) << unit;
    const BrepSolid::Loaded helper =
        BrepSolid::loadFileIsolated(path, "box", BrepSolid::Grouping::Separate, RunControl(), 0);
    EXPECT_EQ(helper.declared_uncertainty, here.declared_uncertainty) << unit;  // bit for bit
  }
}

TEST(StepUncertainty, SharedModelsDeclareTheirs) {
  // Kurbelwelle.stp declares 0.005 mm; presse_asm.step one value per part, the largest
  // 7.418088244970E-2 mm (grep UNCERTAINTY_MEASURE_WITH_UNIT in the files).
  const BrepSolid::Loaded crank = BrepSolid::loadFileIsolated(test::cadDir() + "/Kurbelwelle.stp", "crank",
                                                              BrepSolid::Grouping::Separate, RunControl(), 0);
  EXPECT_DOUBLE_EQ(crank.declared_uncertainty, 0.005);
  const BrepSolid::Loaded presse = BrepSolid::loadFile(test::cadDir() + "/presse_asm.step", "presse",
                                                       BrepSolid::Grouping::Separate);
  EXPECT_DOUBLE_EQ(presse.declared_uncertainty, 7.418088244970E-2);
  // Without transferring the shapes (what the workbench asks of the file FreeCAD imported).
  EXPECT_EQ(declaredStepUncertainty(test::cadDir() + "/presse_asm.step", "presse"), presse.declared_uncertainty);
  EXPECT_EQ(declaredStepUncertainty(test::cadDir() + "/Kurbelwelle.stp", "crank"), crank.declared_uncertainty);
  // part.step declares 1e-6 of its length unit, a CONVERSION_BASED_UNIT 'METRE': 0.001 mm.
  EXPECT_DOUBLE_EQ(declaredStepUncertainty(test::cadDir() + "/part.step", "part"), 1e-3);
}

TEST(StepUncertainty, AFileThatIsNoStepIsAnInputErrorNamingIt) {
  const auto path = std::filesystem::temp_directory_path() / "oraclemesh_not_a_step.step";
  {
    std::ofstream out(path);
    out << "this is no STEP file\n";
  }
  try {
    declaredStepUncertainty(path.string(), "input 'x'");
    FAIL() << "a text file was read as STEP";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("input 'x'", 0), 0u) << e.what();
  }
}

TEST(StepUncertainty, OtherFilesDeclareNone) {
  const auto path = std::filesystem::temp_directory_path() / "oraclemesh_uncertainty_box.brep";
  ASSERT_TRUE(BRepTools::Write(BRepPrimAPI_MakeBox(1, 2, 3).Shape(), path.string().c_str()));
  EXPECT_EQ(BrepSolid::loadFile(path.string(), "box", BrepSolid::Grouping::Separate).declared_uncertainty, 0);
}

}  // namespace
}  // namespace oraclemesh
