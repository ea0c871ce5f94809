#pragma once
// Input angles under the limit where Delaunay refinement needs care (thesis §3.3: Rule Set T
// terminates for angles of 60 degrees and more; Mesh_3's protecting balls cope with smaller
// ones but leave flat elements there). They are listed in the report so the user knows where
// poor elements come from and which part of the CAD model causes them.
#include <string>
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

struct SmallInputAngle {
  // "dihedral": two faces of one input meet along a feature edge at this interior angle;
  // "curves": two feature curves leave a common vertex at this angle;
  // "cone_apex": the full opening angle of a conical face ending in a point.
  std::string kind;
  double angle_deg = 0;
  Point3 location{};  // where the angle is smallest
  std::string input;  // the input(s) the angle belongs to ("a / b" for curves of two inputs)
  int edge = -1;      // 0-based B-rep edge index for "dihedral", -1 otherwise
};

// The input angles under `limitDeg` on the composite boundary: dihedral angles along the B-rep
// edges that are in `features` (so buried edges do not count), angles between feature curves
// at their shared end points, and cone apexes not buried inside a higher-priority input.
// Sorted by angle, smallest first.
std::vector<SmallInputAngle> findSmallInputAngles(const HierarchicalOracle& oracle, const FeatureGraph& features,
                                                  double limitDeg);

}  // namespace oraclemesh
