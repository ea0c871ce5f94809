// Issue 18: every job value a user can get wrong is refused before any geometry is read (or
// right after loading, for what needs the model's size), with its JSON path and the fix: no
// json library message, no wrapped integer, no internal error.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "Error.h"
#include "domain/Sphere.h"
#include "job/JobJson.h"
#include "job/JobSpec.h"
#include "job/Pipeline.h"
#include "job/ResolvedCriteria.h"

#include "input_errors.h"

namespace oraclemesh {
namespace {

using nlohmann::json;
using test::inputErrorOf;

json ball() { return {{"name", "ball"}, {"sphere", {{"center", {0, 0, 0}}, {"radius", 1}}}}; }
json ballJob() { return {{"inputs", {ball()}}}; }
std::string parseError(const json& job) { return inputErrorOf([&] { JobSpec::fromJson(job, "."); }); }
std::string textError(const std::string& text) { return inputErrorOf([&] { JobSpec::fromJsonText(text, "."); }); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(JobValidation, IntegersBeyond32BitsAreRefusedNotTruncated) {
  json job = ballJob();
  job["inputs"][0]["material"] = 4294967297;  // used to be read as material 1
  EXPECT_EQ(parseError(job),
            "inputs[0].material (input 'ball') = 4294967297 is not a whole number from 1 to 2147483647: material ids "
            "are positive integer ids (1, 2, ...)");
  job = ballJob();
  job["element_order"] = 4294967297;  // used to be read as 1
  EXPECT_EQ(parseError(job), "element_order must be 1 (tet4) or 2 (tet10), got 4294967297");
  job = ballJob();
  job["seed"] = 8589934592;
  EXPECT_TRUE(contains(parseError(job), "seed = 8589934592 is not a whole number from 0 to 4294967295"));
  job = ballJob();
  job["limits"] = {{"max_vertices", 1e19}};  // used to wrap to -9223372036854775808
  EXPECT_TRUE(contains(parseError(job), "limits.max_vertices = 1e+19 is not a whole number from 1 to 10000000000"));
  job["limits"] = {{"max_vertices", 5e6}};  // a float without fraction is a count
  EXPECT_EQ(JobSpec::fromJson(job, ".").max_vertices, 5000000);
}

TEST(JobValidation, WrongTypesNameTheirKey) {
  // Used to be nlohmann's "type must be string, but is number" (an internal error).
  json job = {{"inputs", {{{"name", 5}, {"sphere", {{"center", {0, 0, 0}}, {"radius", 1}}}}}}};
  EXPECT_EQ(parseError(job), "inputs[0].name must be a string, got 5: give the input a name, e.g. \"pin\"");
  job = ballJob();
  job["inputs"][0]["role"] = 1;
  EXPECT_EQ(parseError(job), "inputs[0].role must be a string, got 1: use \"material\" or \"cut\"");
  job = ballJob();
  job["optimize"] = {{"perturb", "yes"}};
  EXPECT_EQ(parseError(job), "optimize.perturb must be true or false, got \"yes\"");
  job = ballJob();
  job["criteria"] = {{"default", {{"cell_size", "3"}}}};
  EXPECT_TRUE(contains(parseError(job), "criteria.default.cell_size must be a number, got \"3\""));
  job = ballJob();
  job["output"] = {{"files", {3}}};
  EXPECT_TRUE(contains(parseError(job), "output.files[0] must be a string, got 3"));
  job = ballJob();
  job["inputs"][0]["sphere"]["center"] = {0, "y", 0};
  EXPECT_TRUE(contains(parseError(job), "inputs[0].sphere.center[1] must be a number, got \"y\""));
}

TEST(JobValidation, ContactToleranceIsADistanceAtOrAboveZero) {
  json job = ballJob();
  job["contact_tolerance"] = "0.01";
  EXPECT_EQ(parseError(job), "contact_tolerance must be a number, got \"0.01\": give a distance in model units (mm) "
                             "at or above 0: parts closer than it are bonded");
  job["contact_tolerance"] = -0.01;
  EXPECT_EQ(parseError(job), "contact_tolerance = -0.01 is negative: give a distance in model units (mm) at or above 0 "
                             "(parts closer than it are bonded), or leave it out for the CAD's own tolerance");
  job["contact_tolerance"] = 0;
  EXPECT_EQ(JobSpec::fromJson(job, ".").contact_tolerance, 0.0);
  job["contact_tolerance"] = 0.05;
  EXPECT_EQ(JobSpec::fromJson(job, ".").contact_tolerance, 0.05);
  EXPECT_FALSE(JobSpec::fromJson(ballJob(), ".").contact_tolerance.has_value());
  job.erase("contact_tolerance");
  job["cad_uncertainty"] = -1;
  EXPECT_EQ(parseError(job), "cad_uncertainty = -1 is negative: give the CAD file's declared uncertainty in model "
                             "units (mm), at or above 0");
  job["cad_uncertainty"] = 0.07;
  EXPECT_EQ(JobSpec::fromJson(job, ".").cad_uncertainty, 0.07);
}

TEST(JobValidation, NumbersBeyondDoubleRangeAreNamed) {
  // Used to be "internal error: [json.exception.out_of_range.406] number overflow".
  const std::string message =
      textError(R"({"inputs": [{"name": "b", "sphere": {"center": [0, 0, 0], "radius": 1}}], "criteria": {"default": {"cell_size": 1e999}}})");
  EXPECT_TRUE(contains(message, "number overflow parsing '1e999'") && contains(message, "numbers must be finite"))
      << message;
}

TEST(JobValidation, DeepNestingIsRefusedBeforeParsing) {
  // 100,000 levels used to overflow the stack while the error message was being built.
  const std::string deep = "{\"inputs\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  EXPECT_EQ(textError(deep),
            "the job nests lists and objects more than 64 levels deep (line 1): the job contract needs at most 6 "
            "levels; check how the job file was written");
  // Brackets inside strings do not count.
  const std::string inString = R"({"inputs": [{"name": ")" + std::string(100, '[') +
                               R"(", "sphere": {"center": [0, 0, 0], "radius": 1}}]})";
  EXPECT_EQ(JobSpec::fromJsonText(inString, ".").inputs[0].name, std::string(100, '['));
}

TEST(JobValidation, JobFileOverTheSizeLimitIsRefusedBeforeReading) {
  // Sparse files: a job file one byte over the limit costs no disk and, measured by its size
  // alone, no memory (the CLI and oraclemesh.run check it before reading).
  EXPECT_EQ(jobjson::kMaxBytes, size_t{1} << 30);  // the README's "1 GiB of JSON"
  const auto dir = std::filesystem::temp_directory_path() / ("oraclemesh_job_size_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string over = (dir / "over.json").string(), at = (dir / "at.json").string();
  std::ofstream(over).put(' ');
  std::ofstream(at).put(' ');
  std::filesystem::resize_file(over, jobjson::kMaxBytes + 1);
  std::filesystem::resize_file(at, jobjson::kMaxBytes);
  EXPECT_EQ(inputErrorOf([&] { jobjson::requireJobFileSize(over); }),
            "the job file '" + over + "' is 1073741825 bytes of JSON, more than the limit of 1073741824 bytes (1 GiB): "
            "give large surfaces as STL/OBJ/OFF files instead of 'surface' lists");
  EXPECT_NO_THROW(jobjson::requireJobFileSize(at));
  EXPECT_NO_THROW(jobjson::requireJobFileSize((dir / "missing.json").string()));  // left to the reading
  std::filesystem::remove_all(dir);
  // JSON text is held to the same limit, by its length.
  EXPECT_TRUE(contains(inputErrorOf([] { jobjson::requireJobSize(jobjson::kMaxBytes + 1); }),
                       "the job is 1073741825 bytes of JSON, more than the limit of 1073741824 bytes (1 GiB)"));
}

TEST(JobValidation, OutputsAreCheckedBeforeMeshing) {
  // A missing folder used to be found after meshing, as an "internal error".
  json job = ballJob();
  job["output"] = {{"files", {"no_such_folder/mesh.vtu"}}};
  EXPECT_TRUE(contains(parseError(job), "output.files[0] = './no_such_folder/mesh.vtu': the folder "
                                        "'./no_such_folder' does not exist: create it or fix the path"));
  job["output"] = {{"files", {"mesh.stl"}}};
  EXPECT_TRUE(contains(parseError(job), "output.files[0] = './mesh.stl': unknown extension '.stl'"));
  job["output"] = {{"report", "no_such_folder/report.json"}};
  EXPECT_TRUE(contains(parseError(job), "output.report = './no_such_folder/report.json': the folder"));
}

TEST(JobValidation, SizesFarBelowTheModelNameTheirKey) {
  // A cell size of 1e-300 used to give "about -9223372036854775808 vertices".
  json job = ballJob();
  job["criteria"] = {{"default", {{"cell_size", 1e-300}}}, {"materials", {{"1", {{"edge_size", 1e-9}}}}}};
  JobSpec spec = JobSpec::fromJson(job, ".");
  EXPECT_TRUE(contains(inputErrorOf([&] { resolveCriteria(spec, 3.46); }),
                       "criteria.default.cell_size = 1e-300 is less than a millionth of the model's size"));
  job["criteria"]["default"] = json::object();
  spec = JobSpec::fromJson(job, ".");
  EXPECT_TRUE(contains(inputErrorOf([&] { resolveCriteria(spec, 3.46); }),
                       "criteria.materials.1.edge_size = 1e-09 is less than a millionth"));
  // Above the ratio but over the vertex limit: the estimate is printed as a number, not wrapped.
  job["criteria"] = {{"default", {{"cell_size", 1e-5}}}};  // 3e-6 of the diagonal
  spec = JobSpec::fromJson(job, ".");
  const CriteriaTable table = resolveCriteria(spec, 3.46);
  const HierarchicalOracle oracle({{std::make_shared<Sphere>(Point3{0, 0, 0}, 1.0, "ball"), Role::Material, 1}});
  const std::string message = inputErrorOf([&] { checkExpectedSize(spec, oracle, table); });
  EXPECT_TRUE(contains(message, "would give about 6.3e+15 vertices, more than limits.max_vertices = 5000000")) << message;
}

TEST(JobValidation, CutThatRemovesEverythingSaysSo) {
  // Used to be "the inputs may be smaller than the sizes asked for".
  json cutter = {{"name", "cutter"}, {"sphere", {{"center", {0, 0, 0}}, {"radius", 10}}}, {"role", "cut"}};
  const json job = {{"inputs", {cutter, ball()}}};
  const std::string message = inputErrorOf([&] { runJob(JobSpec::fromJson(job, "."), RunControl()); });
  EXPECT_TRUE(contains(message, "the cut 'cutter' removes everything: every material input ('ball') lies inside a cut"))
      << message;
}

}  // namespace
}  // namespace oraclemesh
