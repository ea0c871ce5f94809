#pragma once
// NRRD label images (http://teem.sourceforge.net/nrrd/format.html), the format 3D Slicer
// and ITK write segmentations in. Supported: 3 axes; integer types (u)int8/16/32 under any
// of NRRD's type names; encodings raw, gzip and ascii; little and big endian; the voxel
// geometry from "space directions" (axis-aligned; a negative direction flips the axis) or
// "spacings", and "space origin" (centre of the first voxel, default 0); attached data or
// one detached "data file" with "line skip" and "byte skip" (-1 for raw: data at the end).
#include <memory>
#include <string>

#include "domain/LabeledImage.h"

namespace oraclemesh {

// InputError naming the input, the file and the fix for anything unreadable or unsupported.
std::shared_ptr<const LabeledImage> readNrrdLabels(const std::string& path, const std::string& inputName);

}  // namespace oraclemesh
