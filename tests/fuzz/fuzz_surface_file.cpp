// The STL / OBJ / OFF reader (one target per extension, ORACLEMESH_FUZZ_EXTENSION): any file
// gives points and triangles or an InputError; nothing else may escape.
#include <cmath>
#include <cstdint>

#include "Error.h"
#include "domain/TriangleSurfaceFile.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = oraclemesh::fuzz::writeInput(data, size, ORACLEMESH_FUZZ_EXTENSION);
  try {
    const oraclemesh::TriangleSoup soup = oraclemesh::readTriangleSurfaceFile(path, "fuzz input");
    // What the reader promises the geometry checks: finite points, indices in range.
    for (const auto& p : soup.points)
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) __builtin_trap();
    for (const auto& t : soup.triangles)
      for (int64_t v : t)
        if (v < 0 || v >= static_cast<int64_t>(soup.points.size())) __builtin_trap();
  } catch (const oraclemesh::InputError&) {
  }
  return 0;
}
