// The NRRD label image reader and the image it builds (labels, counts, components): any file
// gives an image or an InputError; nothing else may escape.
#include <cstdint>

#include "Error.h"
#include "domain/NrrdReader.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = oraclemesh::fuzz::writeInput(data, size, ".nrrd");
  try {
    const auto image = oraclemesh::readNrrdLabels(path, "fuzz input");
    // One query of the interpolated field at the image centre (the margin loop of issue 18).
    oraclemesh::Point3 centre;
    for (int a = 0; a < 3; ++a)
      centre[a] = image->origin()[a] + 0.5 * static_cast<double>(image->size()[a] - 1) * image->spacing()[a];
    image->margin(1, centre);
  } catch (const oraclemesh::InputError&) {
  }
  return 0;
}
