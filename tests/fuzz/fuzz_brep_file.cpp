// The B-rep loading path of a job's file input (one target per extension,
// ORACLEMESH_FUZZ_EXTENSION): BrepSolid::loadFileIsolated, where OpenCASCADE reads the file in
// the helper oraclemesh-shape-reader and this process loads the solids it sends back, then the
// first queries the mesher makes on them (volume, inside, crossings, projection, boundary
// seeds). Any file gives solids or an InputError within the time limit; a crash or sanitizer
// finding here, or any other exception, is a bug. The helper's own crashes are contained by
// design and come back as InputErrors.
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "Error.h"
#include "RunControl.h"
#include "domain/BrepSolid.h"
#include "fuzz_file.h"

namespace {

// The job's limits.time_limit for these small parts: ten times what the seeds take to read,
// and what every input on which OpenCASCADE hangs costs.
constexpr double kTimeLimitSeconds = 3;

bool finite(const oraclemesh::Point3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

void queryLikeTheMesher(const oraclemesh::BrepSolid& solid) {
  const oraclemesh::Bbox box = solid.bbox();
  // The loader's promise (FiniteGeometry, CoordinateRange): a finite box, near enough the origin.
  if (!finite(box.min) || !finite(box.max)) __builtin_trap();
  if (!std::isfinite(solid.volume())) __builtin_trap();
  auto at = [&](double u, double v, double w) {
    return oraclemesh::Point3{box.min[0] + u * (box.max[0] - box.min[0]), box.min[1] + v * (box.max[1] - box.min[1]),
                              box.min[2] + w * (box.max[2] - box.min[2])};
  };
  constexpr int n = 3;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) solid.inside(at((i + 0.3) / n, (j + 0.3) / n, (k + 0.3) / n));
  for (const auto& c : solid.crossings(at(-0.1, 0.4, 0.6), at(1.1, 0.4, 0.6)))
    if (!finite(c.point)) __builtin_trap();
  if (!finite(solid.project(at(0.5, 0.5, 0.5)).point)) __builtin_trap();
  for (const auto& s : solid.boundarySamples(box.diagonal() / 4))
    if (!finite(s.point)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // The helper built beside this target, not one an outer environment points at.
  setenv("ORACLEMESH_SHAPE_READER", ORACLEMESH_FUZZ_SHAPE_READER, 1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = oraclemesh::fuzz::writeInput(data, size, ORACLEMESH_FUZZ_EXTENSION);
  const oraclemesh::RunControl control({}, kTimeLimitSeconds);
  try {
    const auto loaded =
        oraclemesh::BrepSolid::loadFileIsolated(path, "part", oraclemesh::BrepSolid::Grouping::Separate, control, 0);
    if (loaded.solids.empty()) __builtin_trap();  // no solid is an InputError, not an empty result
    for (const auto& solid : loaded.solids) queryLikeTheMesher(*solid);
  } catch (const oraclemesh::InputError&) {
  }
  return 0;
}
