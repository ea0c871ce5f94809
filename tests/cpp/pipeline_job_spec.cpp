// JobSpec's engine and material_assignment: parsed once into enums, refused with the messages
// users have always been given, and named back as the job spells them.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "job/JobSpec.h"

#include "input_errors.h"

namespace oraclemesh {
namespace {

using nlohmann::json;
using test::inputErrorOf;

json ballJob() {
  return {{"inputs", {{{"name", "ball"}, {"sphere", {{"center", {0, 0, 0}}, {"radius", 1}}}, {"material", 1}}}}};
}

JobSpec parse(const json& job) { return JobSpec::fromJson(job, "."); }

TEST(JobSpec, EngineAndMaterialAssignmentDefaultToThesisAndCircumcentre) {
  const JobSpec spec = parse(ballJob());
  EXPECT_EQ(spec.engine, Engine::Thesis);
  EXPECT_EQ(spec.material_assignment, MaterialAssignment::Circumcenter);
}

TEST(JobSpec, EngineNamesParseToTheirEnumAndBack) {
  for (const Engine engine : {Engine::Thesis, Engine::Cgal}) {
    json job = ballJob();
    job["engine"] = engineName(engine);
    EXPECT_EQ(parse(job).engine, engine) << engineName(engine);
  }
  EXPECT_STREQ(engineName(Engine::Thesis), "thesis");
  EXPECT_STREQ(engineName(Engine::Cgal), "cgal");
}

TEST(JobSpec, UnknownEngineIsRefusedWithTheNamesToUse) {
  json job = ballJob();
  job["engine"] = "delaunay";
  EXPECT_EQ(inputErrorOf([&] { parse(job); }),
            "engine must be 'cgal' (Mesh_3) or 'thesis' (Rule Set T), got \"delaunay\"");
  job["engine"] = 3;
  EXPECT_EQ(inputErrorOf([&] { parse(job); }), "engine must be 'cgal' (Mesh_3) or 'thesis' (Rule Set T), got 3");
  job["engine"] = "Thesis";  // names are case-sensitive
  EXPECT_NE(inputErrorOf([&] { parse(job); }), "");
}

TEST(JobSpec, MaterialAssignmentNamesParseToTheirEnumAndBack) {
  for (const MaterialAssignment a : {MaterialAssignment::Circumcenter, MaterialAssignment::Barycenter}) {
    json job = ballJob();
    job["material_assignment"] = materialAssignmentName(a);
    EXPECT_EQ(parse(job).material_assignment, a) << materialAssignmentName(a);
  }
  EXPECT_STREQ(materialAssignmentName(MaterialAssignment::Circumcenter), "circumcenter");
  EXPECT_STREQ(materialAssignmentName(MaterialAssignment::Barycenter), "barycenter");
}

TEST(JobSpec, UnknownMaterialAssignmentAndBarycentreWithMesh3AreRefused) {
  json job = ballJob();
  job["material_assignment"] = "centroid";
  EXPECT_EQ(inputErrorOf([&] { parse(job); }),
            "material_assignment must be \"circumcenter\" or \"barycenter\", got \"centroid\"");
  job["material_assignment"] = "barycenter";
  job["engine"] = "cgal";
  EXPECT_EQ(inputErrorOf([&] { parse(job); }),
            "material_assignment: the 'cgal' engine assigns materials by circumcentre only: use \"circumcenter\" or "
            "engine 'thesis'");
  job["material_assignment"] = "circumcenter";
  EXPECT_EQ(parse(job).engine, Engine::Cgal);
}

}  // namespace
}  // namespace oraclemesh
