#pragma once
// The tets the improvement stage left under 15 degrees, and why: next to a small input angle
// (which no mesh of the model can resolve better than the angle allows) or not improved within
// the stage's work bound.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"
#include "features/InputAngles.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

inline constexpr double kPoorElementDeg = 15;
inline constexpr size_t kPoorElementsListed = 200;

struct PoorElement {
  int64_t tet = -1;
  int material = 0;
  double min_dihedral = 0;  // degrees
  Point3 location{};        // centroid
  int small_angle = -1;     // index into the report's small_input_angles, -1: none near
  double small_angle_distance = 0;
};

struct PoorElements {
  int64_t under5 = 0, under10 = 0, under15 = 0;
  int64_t near_small_angle = 0;     // of those under 15
  std::vector<PoorElement> listed;  // worst first, at most kPoorElementsListed
};

// Curves of the feature graph along which a "dihedral" or "contact" angle lies (the B-rep edge
// of the input it names, or the triangle surface's polyline); empty for the other kinds, which
// have a point.
std::vector<int> curvesOfSmallAngle(const SmallInputAngle& angle, const FeatureGraph& features,
                                    const HierarchicalOracle& oracle);

// A tet is near a small input angle when the angle's point or curve is within one local edge
// size of one of its corners: the job's edge size at the tet (`localEdgeSize`; refinement next
// to a small angle makes tets much smaller than that) or the tet's longest edge, whichever is
// larger. The nearest such angle is named.
PoorElements findPoorElements(const TetMesh& mesh, const std::vector<SmallInputAngle>& angles,
                              const FeatureGraph& features, const HierarchicalOracle& oracle,
                              const std::function<double(const Point3&)>& localEdgeSize = {});

}  // namespace oraclemesh
