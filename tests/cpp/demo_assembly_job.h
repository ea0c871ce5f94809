#pragma once
// The demo assembly job (pin through a plate, a cut box removing one corner of the plate),
// shared by the tests of both engines.
#include <nlohmann/json.hpp>
#include <string>

#include "occt_checks.h"
#include "occt_reference.h"

namespace oraclemesh::test {

// engine empty: the job names none, so it runs on the default engine.
inline nlohmann::json demoAssemblyJob(int order, const std::string& engine = "") {
  const DemoAssembly a;
  nlohmann::json job = {{"inputs",
           {{{"name", "Pin"}, {"brep", brepText(a.pin)}, {"material", 1}},
            {{"name", "CutCorner"}, {"brep", brepText(a.cut)}, {"role", "cut"}},
            {{"name", "Plate"}, {"brep", brepText(a.plate)}, {"material", 2}}}},
          {"criteria",
           {{"default", {{"cell_size", 5}, {"facet_size", 4}, {"facet_distance", 0.2}, {"edge_size", 2}}},
            {"materials", {{"1", {{"cell_size", 3}, {"facet_size", 2}, {"facet_distance", 0.05}}}}}}},
          {"element_order", order},
          {"seed", 0}};
  if (!engine.empty()) job["engine"] = engine;
  return job;
}

}  // namespace oraclemesh::test
