// The `refine` benchmark of issue 7: tetrahedra per second of the thesis engine (Rule Set T)
// against CGAL Mesh_3 on the same oracle and criteria, in the same run. Each model's job is
// run through the pipeline once per engine and repetition, alternating engines so that load
// on the shared machine hits both alike; medians are printed with their ratio.
// Engine seconds = the job's wall time minus the phases both engines share (load, features,
// boundary snap, second order, writing), i.e. refinement plus sliver removal.
//
//   build/oraclemesh_bench_refine [repetitions = 3] [examples dir = examples]
//
// The implant_in_bone inputs come from examples/implant_in_bone/make_implant_in_bone.py.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "Error.h"
#include "job/Pipeline.h"

#include "../cpp/occt_checks.h"
#include "../cpp/occt_reference.h"

namespace {

using namespace oraclemesh;
using nlohmann::json;

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

struct Model {
  std::string name;
  json job;
  std::string baseDirectory;
};

// The demo assembly with the criteria of the pipeline tests (pipeline_demo_assembly.cpp).
Model demoAssembly() {
  const test::DemoAssembly a;
  json job = {{"inputs",
               {{{"name", "Pin"}, {"brep", test::brepText(a.pin)}, {"material", 1}},
                {{"name", "CutCorner"}, {"brep", test::brepText(a.cut)}, {"role", "cut"}},
                {{"name", "Plate"}, {"brep", test::brepText(a.plate)}, {"material", 2}}}},
              {"criteria",
               {{"default", {{"cell_size", 5}, {"facet_size", 4}, {"facet_distance", 0.2}, {"edge_size", 2}}},
                {"materials", {{"1", {{"cell_size", 3}, {"facet_size", 2}, {"facet_distance", 0.05}}}}}}},
              {"element_order", 1},
              {"seed", 0}};
  return {"demo assembly", job, ""};
}

std::optional<Model> implantInBone(const std::string& examples) {
  const std::filesystem::path folder = std::filesystem::path(examples) / "implant_in_bone";
  std::ifstream in(folder / "implant_in_bone.json");
  if (!in || !std::filesystem::exists(folder / "bone.stl")) {
    std::printf("implant_in_bone: inputs missing in %s (run /usr/bin/python3 %s/make_implant_in_bone.py)\n",
                folder.string().c_str(), folder.string().c_str());
    return std::nullopt;
  }
  json job = json::parse(in);
  job.erase("output");
  return Model{"implant_in_bone", job, folder.string()};
}

struct Run {
  int64_t tets = 0;
  double engineSeconds = 0;
};

// nullopt with `why` set when the engine is not in this build.
std::optional<Run> runOnce(const Model& model, const std::string& engine, std::string& why) {
  json job = model.job;
  job["engine"] = engine;
  const auto start = std::chrono::steady_clock::now();
  JobResult result;
  try {
    result = runJob(JobSpec::fromJson(job, model.baseDirectory), RunControl());
  } catch (const InputError& e) {
    const std::string message = e.what();
    if (message.find("engine '" + engine + "'") == std::string::npos || message.find("not available") == std::string::npos)
      throw;
    why = "unavailable";
    return std::nullopt;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double shared = 0;
  for (const char* phase : {"load", "features", "snap", "second_order", "write"})
    shared += result.report["seconds"].value(phase, 0.0);
  return Run{static_cast<int64_t>(result.mesh.tets.size()), wall - shared};
}

struct Column {
  std::string status;  // empty when measured
  std::vector<double> rates;
  std::vector<double> tets;
};

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const std::string examples = argc > 2 ? argv[2] : "examples";
  std::vector<Model> models = {demoAssembly()};
  if (auto m = implantInBone(examples)) models.push_back(*m);

  std::printf("| model | tets thesis | tets Mesh_3 | tets/s thesis | tets/s Mesh_3 | thesis / Mesh_3 |\n");
  std::printf("|---|---:|---:|---:|---:|---:|\n");
  for (const Model& model : models) {
    Column thesis, mesh3;
    try {
      for (int r = 0; r < repetitions; ++r)
        for (auto [engine, column] : {std::make_pair("thesis", &thesis), std::make_pair("cgal", &mesh3)}) {
          if (!column->status.empty()) continue;
          std::string why;
          const std::optional<Run> run = runOnce(model, engine, why);
          if (!run) {
            column->status = why;
            continue;
          }
          column->rates.push_back(run->tets / std::max(run->engineSeconds, 1e-9));
          column->tets.push_back(static_cast<double>(run->tets));
        }
    } catch (const Error& e) {
      std::printf("| %s | failed: %s |||||\n", model.name.c_str(), e.what());
      continue;
    }
    auto cell = [](const Column& c, bool rate) {
      if (!c.status.empty()) return c.status;
      char text[64];
      std::snprintf(text, sizeof text, "%.0f", median(rate ? c.rates : c.tets));
      return std::string(text);
    };
    std::string ratio = "-";
    if (thesis.status.empty() && mesh3.status.empty()) {
      char text[32];
      std::snprintf(text, sizeof text, "%.2fx", median(thesis.rates) / median(mesh3.rates));
      ratio = text;
    }
    std::printf("| %s | %s | %s | %s | %s | %s |\n", model.name.c_str(), cell(thesis, false).c_str(),
                cell(mesh3, false).c_str(), cell(thesis, true).c_str(), cell(mesh3, true).c_str(), ratio.c_str());
    std::fflush(stdout);
  }
  std::printf("\nMedians of %d runs per engine. tets/s = tetrahedra / (job wall time minus the phases both engines "
              "share: load, features, snap, second order, write), i.e. refinement plus sliver removal.\n",
              repetitions);
  return 0;
}
