// Feature figures per shared CAD model (issue: features, closing note): each model meshed by
// the pipeline at default sizes and sharp angle, tet4, sharp edges and junction curves on
// (presse_asm.step as one input per solid, file order = priority). Prints one Markdown row per
// model: feature polylines by kind, pieces added by splitting at crossings, star vertices,
// the feature phase (extraction, clipping, junctions, Rule Set Q preparation, small-angle
// report) and the Mesh_3 seconds, and the small-angle report's summary. A model that fails
// prints its error message instead.
//
//   build/oraclemesh_bench_features [cad dir] [model ...]
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "Error.h"
#include "job/Pipeline.h"

int main(int argc, char** argv) {
  using namespace oraclemesh;
  const std::string dir = argc > 1 ? argv[1] : "../shared/data/cad";
  std::vector<std::string> models = {"part.step",     "screw.step",      "Kurbelwelle.stp",
                                     "U_Joint_2.stp", "presse_asm.step", "cube_filet.stp"};
  if (argc > 2) models.assign(argv + 2, argv + argc);
  std::printf("| model | sharp-edge polylines | junction polylines | crossing pieces | star vertices | "
              "features s | Mesh_3 s | vertices | angles < 60 deg | smallest (kind) |\n"
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  for (const std::string& model : models) {
    const nlohmann::json job = {{"inputs", {{{"name", model}, {"file", dir + "/" + model}}}},
                                {"element_order", 1},
                                {"seed", 0}};
    try {
      const JobResult result = runJob(JobSpec::fromJson(job, ""), RunControl());
      const nlohmann::json& r = result.report;
      const nlohmann::json& f = r.at("features");
      const nlohmann::json& angles = r.at("small_input_angles");
      std::string smallest = "-";
      if (!angles.empty()) {
        char text[96];
        std::snprintf(text, sizeof text, "%.3g (%s)", angles[0].at("angle_deg").get<double>(),
                      angles[0].at("kind").get<std::string>().c_str());
        smallest = text;
      }
      std::printf("| %s | %lld | %lld | %lld | %lld | %.2f | %.1f | %zu | %zu | %s |\n", model.c_str(),
                  f.at("sharp_edge_polylines").get<long long>(), f.at("junction_polylines").get<long long>(),
                  f.at("crossing_pieces").get<long long>(), f.at("star_vertices").get<long long>(),
                  r.at("seconds").at("features").get<double>(), r.at("seconds").at("mesh3").get<double>(),
                  result.mesh.points.size(), angles.size(), smallest.c_str());
    } catch (const Error& e) {
      std::printf("| %s | failed: %s |\n", model.c_str(), e.what());
    }
    std::fflush(stdout);
  }
  return 0;
}
