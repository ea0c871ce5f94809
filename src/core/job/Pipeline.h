#pragma once
// Runs a job end to end: inputs -> oracle -> features -> engine -> exact boundary nodes ->
// second order -> quality report -> files. The CLI, the Python module and FreeCAD all come
// through here, so they all behave the same.
#include <nlohmann/json.hpp>

#include "RunControl.h"
#include "job/JobSpec.h"
#include "mesh/Surfaces.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

struct JobResult {
  TetMesh mesh;
  nlohmann::json report;
  // Interfaces and exteriors as element faces, named as in the report and the INP, so that
  // callers (FreeCAD's face groups) need not find and name them again.
  std::vector<MeshSurface> surfaces;
  std::vector<std::string> surface_names;  // one per surface
};

// Throws InputError (bad job or input; MeshCheckError, a mesh the self-check refused), LimitError
// (vertex / time limit) or Cancelled. output.report is written either way: "status" says how the
// job ended (JobReport.h).
JobResult runJob(const JobSpec& job, const RunControl& control);

// What the CLI and the report of a stopped job say when memory runs out.
inline constexpr const char* kOutOfMemoryMessage =
    "out of memory: coarsen the sizes (criteria) or lower limits.max_vertices";

// The library version reported in every report.
const char* version();

}  // namespace oraclemesh
