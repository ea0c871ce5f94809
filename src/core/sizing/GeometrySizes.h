#pragma once
// The size samples the geometry of the inputs asks for (issue 16's sizing field): curvature of
// the B-rep faces, short sharp edges, and the thickness of walls, each turned into a size by a
// fineness preset. The samples become a SizeField (sizing/SizeField.h).
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "sizing/Fineness.h"
#include "sizing/SizeField.h"

namespace oraclemesh {

class RunControl;

struct GeometrySizes {
  std::vector<SizeSample> samples;
  // The vertices the sizes asked for would make on the B-rep faces (faces a higher input hides
  // count too: an estimate for orders of magnitude), the entry contributing most, and the
  // smallest size asked on that entry.
  double surface_vertices = 0;
  int largest_entry = -1;
  SizeSample smallest;
};

// The sizes every B-rep entry's faces and edges ask for, from their tessellation: curvature,
// wall thickness and (sharpAngleDeg > 0) short sharp edges, at most `cap`. Triangle surfaces
// and images add none yet. When the surface estimate passes `vertexLimit`, no samples are
// made (the caller refuses the job).
GeometrySizes geometrySizes(const HierarchicalOracle& oracle, const FinenessPreset& fineness, double sharpAngleDeg,
                            double cap, double vertexLimit, const RunControl& control);

}  // namespace oraclemesh
