#pragma once
// Parts the mesh joins where the inputs do not touch. A tetrahedron that reaches across a gap
// narrower than itself ties two parts together: the mesh shares nodes there, the solver bonds
// them, and neither volume need change by as much as 1 %. Every vertex of a mesh face between
// two parts lies on both parts' boundaries where they touch (the snap puts it on the CAD), so
// a face none of whose vertices is on both parts lies across a gap. (One or two vertices off
// is what a face at the edge of a contact has when the mesh's interface edge is a chord away
// from the CAD's, as where no feature curve marks it.)
#include <vector>

#include "Geometry.h"
#include "domain/HierarchicalOracle.h"
#include "mesh/TetMesh.h"
#include "sizing/BondedWedges.h"

namespace oraclemesh {

struct JoinedAcrossGap {
  int material = 0;            // the smaller id of the two
  int other_material = 0;
  double interface_area = 0;   // of all mesh faces between the two materials
  // Of that, where the parts lie farther apart than the tolerance (the gap interpolated
  // linearly over each face from its vertices): the band the mesh bonds beside a tangent
  // contact (BondedWedges.h), a strip along a contact's edge that no feature curve holds on
  // the CAD (its nodes a chord off both parts), and any joined area. The rest is where the
  // parts touch.
  double beyond_contact_area = 0;
  double joined_area = 0;      // of those with no vertex within the tolerance of both parts
  double widest_gap = 0;       // the largest over those faces of their vertices' smallest distance
                               // from the farther part: about the gap's width
  Point3 widest_at{};          // that vertex
};

// One entry per pair of materials sharing mesh faces, sorted by material pair (measureInterfaceGaps);
// findPartsJoinedAcrossGaps keeps the pairs with faces none of whose vertices is within
// `tolerance` of the closures of both materials' inputs (inside an input, or on its boundary
// to `tolerance`). `distanceKeptOffCad` (empty, or one per vertex):
// how far the snap left each vertex off the CAD, allowed on top of `tolerance` at that vertex
// alone (one node left off elsewhere must not hide a gap bridged here). `bondedWedges` (may be
// null): a wedge bonded beside a tangent contact allows its width at the vertices within its
// reach, as the tolerance does everywhere.
std::vector<JoinedAcrossGap> measureInterfaceGaps(const TetMesh& mesh, const HierarchicalOracle& oracle,
                                                  double tolerance,
                                                  const std::vector<double>& distanceKeptOffCad = {},
                                                  const BondedWedges* bondedWedges = nullptr);
// The pairs of `measured` that the mesh joins across a gap (some joined area).
std::vector<JoinedAcrossGap> joinedPairs(const std::vector<JoinedAcrossGap>& measured);
std::vector<JoinedAcrossGap> findPartsJoinedAcrossGaps(const TetMesh& mesh, const HierarchicalOracle& oracle,
                                                       double tolerance,
                                                       const std::vector<double>& distanceKeptOffCad = {},
                                                       const BondedWedges* bondedWedges = nullptr);

}  // namespace oraclemesh
