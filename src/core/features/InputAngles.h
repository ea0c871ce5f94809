#pragma once
// Input angles under the limit where Delaunay refinement needs care (thesis §3.3.2: Rule Set T
// terminates for angles of 60 degrees and more; Mesh_3's protecting balls cope with smaller
// ones but leave flat elements there). They are listed in the report so the user knows where
// poor elements come from and which part of the CAD model causes them.
#include <string>
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"
#include "features/JunctionCurves.h"

namespace oraclemesh {

struct SmallInputAngle {
  // "dihedral": two faces of one input meet along a feature edge at this interior angle (for a
  // triangle surface, its two triangles along a sharp edge; `edge` is then -1);
  // "curves": two feature curves leave a common vertex at this angle;
  // "cone_apex": the full opening angle of a conical face ending in a point;
  // "junction": a material wedge where the boundaries of two inputs cross (the plate's wedge
  // under a pin entering it at a shallow angle), from their exact face normals;
  // "contact": a wedge (of a material or of the outside) along a sharp B-rep edge where the
  // faces of other inputs touch it, such as the air gap between a nut's top chamfer and the
  // flat part resting on the nut; measured from oracle labels around the edge (5 degree steps).
  std::string kind;
  double angle_deg = 0;
  Point3 location{};  // where the angle is smallest
  std::string input;  // the input(s) the angle belongs to ("a / b" for curves of two inputs)
  int edge = -1;      // 0-based B-rep edge index for "dihedral" and "contact", -1 otherwise
  int curve = -1;     // the feature curve of a triangle surface's "dihedral", -1 otherwise
};

// Unit direction in which polyline `pl` leaves its end point (its front, or its back when
// `atBack`): the exact tangent of its curve there (B-rep edges through BRepLProp, junction
// curves as the cross product of their two faces' normals), signed to run into the polyline;
// the end segment itself for user polylines and where the exact tangent is undefined. Chords
// would shrink the angle between two curves leaving a vertex tangentially with the sampling.
Point3 leavingDirection(const HierarchicalOracle& oracle, const FeaturePolyline& pl, const JunctionCurves* junctions,
                        bool atBack);

// The input angles under `limitDeg` on the composite boundary: dihedral angles along the B-rep
// edges and triangle-surface sharp edges that are in `features` (so buried edges do not
// count), angles between feature curves
// at their shared end points, and cone apexes not buried inside a higher-priority input.
// With `junctions` (the curves the junction polylines of `features` run along), also the
// composite material wedges along those polylines: at each inner polyline point the two
// inputs' faces cut the plane normal to the curve into four sectors; neighbouring sectors of
// one material form a wedge, and the smallest wedge of any material along the curve counts.
// Sorted by angle, smallest first.
std::vector<SmallInputAngle> findSmallInputAngles(const HierarchicalOracle& oracle, const FeatureGraph& features,
                                                  double limitDeg, const JunctionCurves* junctions = nullptr);

}  // namespace oraclemesh
