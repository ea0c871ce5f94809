#pragma once
// The size samples the geometry of the inputs asks for (issue 16's sizing field): curvature of
// the B-rep faces and of discrete surfaces, short sharp edges, and the thickness of walls, each
// turned into a size by a fineness preset. The samples become a SizeField (sizing/SizeField.h).
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "sizing/BondedWedges.h"
#include "sizing/Fineness.h"
#include "sizing/SizeField.h"

namespace oraclemesh {

class RunControl;

// The narrowest gap the sizing found between two B-rep entries (oracle entry indices).
struct PartGap {
  int entry = -1, other = -1;  // entry < other
  double width = 0;            // between the exact faces
  Point3 at{};                 // on entry's face
};

struct GeometrySizes {
  std::vector<SizeSample> samples;      // curvature, thickness, short edges (with a fineness)
  std::vector<SizeSample> gap_samples;  // gaps between entries (always)
  // The vertices the sizes asked for would make on the B-rep faces (faces a higher input hides
  // count too: an estimate for orders of magnitude), the entry contributing most, and the
  // smallest size asked on that entry.
  double surface_vertices = 0;
  int largest_entry = -1;
  SizeSample smallest;
  // Per pair of entries with a gap wider than the contact tolerance: its narrowest place,
  // narrowest first.
  std::vector<PartGap> gaps;
  // Wedges beside tangent contacts left bonded instead of sized (sizing/BondedWedges.h).
  std::vector<BondedWedgeSample> bonded_wedges;
};

// The sizes every B-rep entry's faces and edges ask for, from their tessellation, at most
// `cap`: with a fineness, curvature, wall thickness and (sharpAngleDeg > 0) short sharp edges;
// with or without one, gaps to other entries wider than `contactTolerance` (narrower ones
// touch), w / sizesPerGap for a gap of width w, except in the wedges beside tangent contacts
// (BondedWedges.h), which are bonded. Triangle surfaces and image labels ask for the
// same from their discrete surfaces (sizing/DiscreteSurface.h), short edges excepted.
// When the surface estimate passes `vertexLimit`, no samples are made (the caller refuses the
// job).
GeometrySizes geometrySizes(const HierarchicalOracle& oracle, const FinenessPreset* fineness, double sizesPerGap,
                            double sharpAngleDeg, double cap, double contactTolerance, double vertexLimit,
                            const RunControl& control);

}  // namespace oraclemesh
