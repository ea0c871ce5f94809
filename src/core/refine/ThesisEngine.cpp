// Rule Set T (thesis §3.3.1) on a CGAL Delaunay triangulation: the driver. The levels are
// refined in the thesis' order, each one step at a time and only while the levels before it
// have nothing to do, as CGAL Mesh_3 chains its mesher levels:
//   T1  constrained subsegments (ConstrainedSegments.cpp)
//   TP  planar faces, when the job asks for them (PlanarFaceLayer.cpp, through RefinementHook)
//   T2  restricted facets (RestrictedFacets.cpp)
//   T3  cells inside the materials (Cells.cpp)
// Beyond the thesis, once T1-T3 have converged: the sliver rule (SliverRule.cpp) and rule P,
// vertex moves (VertexMoves.cpp). RuleSetTRefiner.h lists the other files.
#include "refine/ThesisEngine.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "Error.h"
#include "refine/PlanarFaceLayer.h"
#include "refine/RuleSetTRefiner.h"

namespace oraclemesh {
namespace refine {
namespace {

// The smallest size asked for at a point / the terminator length there.
constexpr double kSizePerTerminator = 32;

}  // namespace

RuleSetTRefiner::RuleSetTRefiner(const HierarchicalOracle& oracle, const FeatureGraph& features,
                                 const RuleSetTOptions& options, const RunControl& control, RuleSetTStatistics& stats)
    : oracle_(oracle), features_(features), options_(options), control_(control), stats_(stats) {
  const double diag = oracle.diagonal();
  reach_ = 4 * diag;
  double smallest = std::numeric_limits<double>::infinity();
  auto consider = [&](const MaterialCriteria& c) {
    for (double v : {c.cell_size, c.facet_size, c.edge_size})
      if (v > 0) smallest = std::min(smallest, v);
  };
  consider(options.criteria.defaults);
  for (const auto& [m, c] : options.criteria.per_material) consider(c);
  if (!std::isfinite(smallest)) smallest = diag / 15;
  capsTerminator_ = smallest / kSizePerTerminator;
  // The gap sizes lower every facet size and the feature edges' size (kEdgeSizePerSize times
  // them, CriteriaTable::*SizeAt): the terminator follows the smaller.
  if (options.criteria.gap_field) terminatorPerGapSize_ = std::min(1.0, kEdgeSizePerSize) / kSizePerTerminator;
  // The contact-end criteria (FacetCriteria.h) refine towards the curve where three regions
  // meet. Where that curve is a constrained segment (a B-rep part's edge, a junction) its
  // protection ends the refinement; where inputs have no feature curves (triangle surfaces,
  // images, features off) the refinement chases it down to the terminator length and leaves
  // facets with corners off the contact there, worse than none.
  if (options.criteria.contact_tolerance > 0 && !features.empty()) {
    std::set<int> withoutCurves;
    for (const OracleEntry& e : oracle.entries())
      if (e.material > 0 && !e.source->brepTopology()) withoutCurves.insert(e.material);
    for (const OracleEntry& e : oracle.entries())
      if (e.material > 0 && !withoutCurves.count(e.material)) contactEndMaterials_.insert(e.material);
  }
}

double RuleSetTRefiner::terminatorAt(const Point3& p) const {
  if (!(terminatorPerGapSize_ > 0)) return capsTerminator_;
  return std::min(capsTerminator_, terminatorPerGapSize_ * options_.criteria.gap_field->at(p));
}

CriteriaTable::FieldValues RuleSetTRefiner::fieldsBelow(const Point3& p, const VH* vertices, int count) const {
  const CriteriaTable& criteria = options_.criteria;
  CriteriaTable::FieldValues below;
  if (criteria.field) below.field = 0;
  if (criteria.gap_field) below.gap = 0;
  if (criteria.cell_field) below.cell = 0;
  if (!criteria.varies()) return below;
  for (int k = 0; k < count; ++k) {
    VertexInfo& info = vertices[k]->info();
    const Point3 at = toPoint3(vertices[k]->point());
    if (!(info.fieldsReadAt == at)) {
      info.fields = criteria.fieldsAt(at);
      if (criteria.cell_field) info.fields.cell = criteria.cell_field->at(at);
      info.fieldsReadAt = at;
    }
    const double d = distance(p, at);
    // The relative margin covers the rounding of both sides of the Lipschitz inequality.
    if (criteria.field)
      below.field = std::max(below.field, (info.fields.field - criteria.field->grading() * d) * (1 - 1e-9));
    if (criteria.gap_field)
      below.gap = std::max(below.gap, (info.fields.gap - criteria.gap_field->grading() * d) * (1 - 1e-9));
    if (criteria.cell_field)
      below.cell = std::max(below.cell, (info.fields.cell - criteria.cell_field->grading() * d) * (1 - 1e-9));
  }
  return below;
}

bool RuleSetTRefiner::belowTerminator(const Zone& zone) const {
  if (!(zone.insertionRadius < capsTerminator_)) return false;  // the length is at most that: no query
  return zone.insertionRadius < terminatorAt(toPoint3(zone.point));
}

// Next to a small input angle the caps' length holds, as the terminators there need: gap
// sizes fall to their floor where touching parts close a tangent contact (a small angle of
// kind contact), and a wedge's own thickness falls to zero (T1.3 split screw.step's 45-degree
// edges on without end when the terminator followed the whole field).
bool RuleSetTRefiner::belowTerminator(const Subsegment& s) const {
  const double half = length(s) / 2;
  if (half >= capsTerminator_) return false;
  return nearSmallAngle(s) || half < terminatorAt(toPoint3(CGAL::midpoint(s.a->point(), s.b->point())));
}

TetMesh RuleSetTRefiner::run() {
  auto t0 = std::chrono::steady_clock::now();
  auto phase = [&](const std::string& name) {
    const auto now = std::chrono::steady_clock::now();
    stats_.seconds[name] += std::chrono::duration<double>(now - t0).count();
    t0 = now;
  };
  const char* current = "initial_points";  // booked also when a limit stops it
  try {
    control_.report("initial points", 0);
    insertInitialPoints();
    phase(current);
    current = "refine";
    control_.report("refine", 0);
    refine();
    phase(current);
    current = "sliver_rule";
    refineSlivers();
    phase(current);
  } catch (const LimitError&) {
    phase(current);
    stats_.partial = extract();
    throw;
  }
  if (hook_) {
    hook_->refinementDone();
    phase(hook_->checkPhase());
  }
  // The elements left are Rule Set T's; the vertex moves after it aim at dihedral angles
  // only (like CGAL's perturbation, which ran after the engine before them).
  listLeftElements();
  perturbSlivers();
  phase("vertex_moves");
  keepSubsegmentsInMaterial();
  TetMesh mesh = extract();
  listLeftSlivers();
  phase("extract");
  finalCheck();
  return mesh;
}

void RuleSetTRefiner::refine() {
  int64_t steps = 0;
  const double expected = options_.max_vertices > 0 ? static_cast<double>(options_.max_vertices) / 20 : 1e5;
  while (true) {
    if ((++steps & 63) == 0) {
      control_.checkpoint();
      if ((steps & 4095) == 0) control_.report("refine", std::min(0.99, dt_.number_of_vertices() / expected));
    }
    if (refineOneSegment() || (hook_ && hook_->refineOne()) || refineOneFacet() || refineOneCell()) continue;
    // The queues are empty: the levels look again, in their order, for work their queues lost.
    bool again = queueBadSegments();
    if (!again && hook_) again = hook_->queuesEmptied();
    if (!again) break;
  }
}

}  // namespace refine

namespace {

void validate(const HierarchicalOracle& oracle, const RuleSetTOptions& options) {
  auto check = [](const MaterialCriteria& c, const std::string& what) {
    if (!(c.cell_size > 0) || !(c.facet_size > 0) || !(c.facet_distance > 0))
      throw InputError("criteria " + what + ": the thesis engine needs positive cell_size, facet_size and facet_distance");
    if (c.cell_radius_edge_ratio != 0 && c.cell_radius_edge_ratio < 1)
      throw InputError("criteria " + what + ": cell_radius_edge_ratio must be at least 1 (or 0 = off); the thesis "
                       "uses 1.1 to 2");
  };
  check(options.criteria.defaults, "default");
  for (const auto& [m, c] : options.criteria.per_material) check(c, "of material " + std::to_string(m));
  if (!(oracle.diagonal() > 0)) throw InputError("the inputs have no extent: nothing to mesh");
}

}  // namespace

TetMesh meshWithRuleSetT(const HierarchicalOracle& oracle, const FeatureGraph& features,
                         const RuleSetTOptions& options, const RunControl& control, RuleSetTStatistics* statistics) {
  validate(oracle, options);
  RuleSetTStatistics local;
  RuleSetTStatistics& stats = statistics ? *statistics : local;
  refine::RuleSetTRefiner refiner(oracle, features, options, control, stats);
  std::unique_ptr<refine::PlanarFaceLayer> planarFaces;
  if (!options.planar_faces.empty()) {
    planarFaces = std::make_unique<refine::PlanarFaceLayer>(refiner);
    refiner.setHook(planarFaces.get());
  }
  TetMesh mesh = refiner.run();
  if (mesh.tets.empty())
    throw NoTetrahedraError("the thesis engine produced no tetrahedra: the inputs may be smaller than the sizes asked for; "
                     "lower cell_size and facet_size below the smallest part's thickness.");
  return mesh;
}

}  // namespace oraclemesh
