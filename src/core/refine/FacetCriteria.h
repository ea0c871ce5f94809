#pragma once
// The facet criteria of Rule Set T's T2 (thesis §3.3.1: a restricted facet without its three
// vertices on the boundary, or whose surface Delaunay ball is too big), as Mesh_3 reads the
// job's criteria (facet_size, facet_distance, facet_angle), as small objects on plain points:
// no triangulation is needed to test them. A facet between two materials meets the
// strictest bound of the two; label 0 (outside) sets none.
#include <array>

#include "Geometry.h"
#include "MeshCriteria.h"

namespace oraclemesh::refine {

// What the facet criteria look at: a restricted facet and its surface Delaunay ball.
struct FacetShape {
  std::array<Point3, 3> corners{};  // in the triangulation's order
  Point3 ballCentre{};              // where the facet's dual edge crosses the boundary
  int labelA = 0, labelB = 0;       // the materials on the two sides of that crossing
  bool cornersOnBoundary = true;    // false when a corner is an interior (or infinite) vertex
  double bridge = 0;                // empty space the dual edge crosses between two materials
  bool offInterface = false;        // between two materials: a corner off one of the parts
  bool acrossSharpEdge = false;     // two corners on two faces of one B-rep meeting at under 60 degrees
};

// The facet's three vertices must lie on the boundary (T2's first premise).
struct FacetOnBoundaryCriterion {
  static constexpr double kExcess = 1e6;  // its badness: before any facet too big
  bool fails(const FacetShape& f) const { return !f.cornersOnBoundary; }
};

// Surface Delaunay ball radius above facet_size.
struct FacetSizeCriterion {
  double bound = 0;  // infinity when neither side has a bound
  static double ballRadius(const FacetShape& f);
  bool fails(double radius) const { return bound > 0 && radius > bound; }
};

// Distance from the facet's circumcentre to its ball centre above facet_distance.
struct FacetDistanceCriterion {
  double bound = 0;
  static double distance(const FacetShape& f);
};

// Smallest facet angle below facet_angle in degrees. Mesh_3 caps the bound at 30 degrees,
// where surface refinement still terminates.
struct FacetAngleCriterion {
  static constexpr double kCap = 30;
  double bound = 0;  // already capped
  static double smallestAngleDeg(const FacetShape& f);
  bool applies() const;
};

// A facet between two materials whose dual edge crosses empty space wider than the contact
// tolerance joins two parts across a gap or a wedge that the mesh does not have yet (a nut's
// chamfer under a plate): the cells on either side are labelled by circumcentres beyond it.
// Parts closer than the tolerance touch, so narrower empty space is no gap.
struct FacetBridgeCriterion {
  // Its badness: a fixed priority, as for a facet too big (how much wider than the tolerance
  // says nothing about how wrong the facet is; at a tolerance of 1e-6 of the model every
  // bridge would come first).
  static constexpr double kExcess = 2;
  double bound = 0;  // the contact tolerance; 0: off
  bool fails(const FacetShape& f) const { return bound > 0 && f.bridge > bound; }
};

// A facet between two materials with a corner farther than the contact tolerance from one of
// the parts puts the interface where they do not touch: where a contact ends in a wedge
// (a chamfer leaving a plate's face), a coarse facet joins the contact's edge to a vertex on
// the chamfer, and the void under it meshes as the other part.
struct FacetOnInterfaceCriterion {
  static constexpr double kExcess = 2;  // its badness, as for a bridge
  double bound = 0;                     // the contact tolerance; 0: off
  bool fails(const FacetShape& f) const { return bound > 0 && f.offInterface; }
};

// A facet with corners on two faces that meet at a dihedral angle under 60 degrees spans the
// thin wedge beside their edge instead of meeting the edge's chain of subsegments: the wedge's
// tip under it is left out of the mesh as a notch of void, with flat tets at its rim that no
// improvement can take (screw.step's 45-degree chamfer meeting its slot; facet size and
// distance miss it when the wedge is thinner than facet_distance). Such a facet is bad when it
// lies deeper than half the facet distance bound (measured as FacetDistanceCriterion does): a
// shallower one is a chord of the wedge's tip within the surface tolerance, and Rule Set T,
// which keeps surface vertices only out of the subsegments' diametral balls, cannot take
// every facet out of a wedge that acute.
struct FacetAcrossSharpEdgeCriterion {
  static constexpr double kExcess = 2;       // its badness, as for a bridge
  static constexpr double kDepthShare = 0.5;  // of facet_distance
  double depthBound = 0;                     // no positive finite bound: every such facet fails
  bool fails(const FacetShape& f) const;
};

struct FacetVerdict {
  double badness = 0;       // how far beyond the worst failing criterion (> 1); 0 = good
  const char* reason = "";  // the criterion that set badness
};

class FacetCriteria {
 public:
  explicit FacetCriteria(const CriteriaTable& table) : table_(table) {}
  // withAngle = false leaves facet_angle out (the refiner's terminator asks whether a facet
  // fails for its angle alone). `below`, when given, holds lower bounds of the fields at the
  // ball centre (RuleSetTRefiner::fieldsBelow): a facet that meets its criteria with them is
  // good without reading the fields there.
  FacetVerdict judge(const FacetShape& f, bool withAngle = true,
                     const CriteriaTable::FieldValues* below = nullptr) const;

  // The smallest bound over the positive materials on either side (infinity: none): of a
  // constant criterion, or of a size from the fields at the facet's ball centre (CriteriaTable::facetSize).
  double bound(const FacetShape& f, double MaterialCriteria::*field) const;
  double bound(const FacetShape& f, const CriteriaTable::FieldValues& at,
               double (CriteriaTable::*size)(int, const CriteriaTable::FieldValues&) const) const;

 private:
  FacetVerdict judgeWith(const FacetShape& f, bool withAngle, const CriteriaTable::FieldValues& at) const;

  const CriteriaTable& table_;
};

}  // namespace oraclemesh::refine
