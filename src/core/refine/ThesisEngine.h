#pragma once
// The thesis' refiner (Rule Set T = Rule Set Q + Rule Set S++, thesis §3.3.1) behind a plain
// interface: no CGAL type crosses this header, so only refine/'s own files (those that
// include RuleSetTRefiner.h) pay for the Delaunay triangulation templates.
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "MeshCriteria.h"
#include "RunControl.h"
#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"
#include "mesh/TetMesh.h"
#include "refine/PlanarFacets.h"

namespace oraclemesh {

struct RuleSetTOptions {
  CriteriaTable criteria;
  MaterialAssignment assignment = MaterialAssignment::Circumcenter;  // Pons 2007 / thesis §4.1
  std::vector<Point3> initial_points;  // the job's initial_points, inserted as interior points
  int64_t max_vertices = 0;            // 0 = no limit; reaching it throws LimitError
  unsigned seed = 0;                   // order of the boundary seeds (the only random choice)
  // Where the input has angles under 60 degrees (InputAngles): feature curves along a sharp
  // dihedral edge and points (star vertices, cone apexes). Cells near them that fail only the
  // radius-edge bound are left (terminator rule) instead of splitting segments without end.
  std::vector<int> small_angle_curves;
  std::vector<Point3> small_angle_points;
  // (oracle entry, face, face) with the smaller face first, for the two faces of each B-rep
  // edge along a dihedral angle under 60 degrees: a restricted facet with corners on both
  // spans the thin wedge there and is refined (FacetCriteria.h).
  std::set<std::tuple<int, int, int>> faces_meeting_at_small_dihedrals;
  // Planar faces whose triangles are recovered as 3D facets (features.planar_faces; empty =
  // off). Their borders must be constrained segments of `features` (findPlanarFaces).
  std::vector<PlanarFace> planar_faces;
  // Beyond the thesis: once T1-T3 have converged, the sliver rule inserts points near cells
  // with a dihedral angle below this bound in degrees (slivers, which the radius-edge bound
  // lets through), and rule P then moves vertices of those left; 0 = off.
  double sliver_dihedral_deg = 0;
  // The point of feature curve `curve` nearest to p (empty = segment vertices lie on the
  // polylines' chords). Inner polyline points and T1 splits go onto the curves with it, so
  // they need no move after refinement: the boundary snap would otherwise move them by the
  // chord's sagitta and flatten cells.
  std::function<Point3(int curve, const Point3& p)> onto_curve;
};

// A triangle of a planar face's 2D Delaunay triangulation that is no 3D facet at the end.
struct MissingPlanarTriangle {
  int entry = -1, face = -1;
  Point3 circumcentre{};
  double radius = 0;
  std::string reason;  // why its circumcentre was not inserted
};

// What the planar-face layer did (all zero when it is off).
struct PlanarFaceStatistics {
  int64_t faces = 0;                  // planar faces with triangles on the composite boundary
  int64_t triangles = 0;              // their restricted 2D Delaunay triangles at the end
  int64_t missing_at_first_check = 0; // of those, not 3D facets when the layer first looked
  int64_t insertions = 0;             // points the layer inserted (circumcentres, segment splits)
  int64_t missing = 0;                // not 3D facets at the end
  std::vector<MissingPlanarTriangle> missing_triangles;  // the first 200 of them
};

// An element the refiner left although it violates its criteria, and why.
struct LeftElement {
  std::string kind;    // "cell" or "facet"
  std::string reason;  // which criterion fails and why it was not refined
  Point3 location{};   // circumcentre (cell) or surface Delaunay ball centre (facet)
  int material = 0;
  double value = 0;    // the violating measure (radius-edge ratio, circumradius, ...)
};

struct RuleSetTStatistics {
  std::map<std::string, double> seconds;     // per phase
  // Points inserted, per rule: T1.1, T1.2, "T1.2 shell", T1.3, T2.1, T2.2, T3.1-T3.4, TP.1, TP.2 and
  // the sliver rule's sliver.near_centre, sliver.segment, sliver.ball_segment, sliver.ball_centre.
  std::map<std::string, int64_t> insertions;
  int64_t vertex_moves = 0;           // rule P's moves (they insert nothing)
  int64_t encroachment_refusals = 0;  // times the T1.2 terminator left a subsegment encroached
                                      // (a subsegment may be refused more than once)
  int64_t initial_points = 0;
  int64_t star_vertices = 0;
  int64_t constrained_subsegments = 0;        // at the end
  std::vector<LeftElement> left;  // the worst 200 elements left
  int64_t elements_left_total = 0;  // all of them
  // Cells the sliver rule and rule P left under options.sliver_dihedral_deg (value: the
  // smallest dihedral angle): the worst 200, and the count of all.
  std::vector<LeftElement> slivers_left;
  int64_t slivers_left_total = 0;
  // Checked once at the end, by other means than the refinement uses (nearest-vertex
  // queries): subsegments that are not Delaunay edges or have a vertex in their diametral
  // ball, restricted facets with a vertex off the boundary. All zero unless elements are left.
  int64_t subsegments_not_edges = 0;
  // Delaunay edges of no cell with a material label: not in the mesh (T1.3 leaves none when
  // some cell around each has its barycentre in a material).
  int64_t subsegments_outside_material = 0;
  // T1.3's last resort: subsegments kept in the mesh by labelling the cells around them by
  // their barycentre, and how many cells that labelled.
  int64_t subsegments_kept_by_barycentre = 0;
  int64_t cells_labelled_by_barycentre = 0;
  int64_t encroached_subsegments = 0;
  int64_t restricted_facets_off_boundary = 0;
  PlanarFaceStatistics planar;
  // When a limit stops the refinement: the cells with label > 0 at that moment, for inspection.
  TetMesh partial;
};

// Meshes the composite domain of `oracle` by Rule Set T with the polylines of `features` as
// constrained segments (empty = the featureless approach). Every constrained subsegment is an
// edge of the result (listed in feature_edges with its curve id). Vertices inserted on the
// boundary are exact oracle crossings; vertices on segments lie on the curves when
// options.onto_curve is set (else on the chords, and the pipeline puts them on the curves).
// Throws LimitError (vertex or time limit; the mesh so far is left in statistics->partial),
// Cancelled.
TetMesh meshWithRuleSetT(const HierarchicalOracle& oracle, const FeatureGraph& features,
                         const RuleSetTOptions& options, const RunControl& control,
                         RuleSetTStatistics* statistics = nullptr);

}  // namespace oraclemesh
