#include "job/FeatureAssembly.h"

#include <BRepExtrema_DistShapeShape.hxx>
#include <Standard_Failure.hxx>

#include <cmath>
#include <optional>
#include <sstream>

#include "Error.h"
#include "domain/BrepTopology.h"
#include "features/BrepSharpEdges.h"
#include "features/CoincidentFeatures.h"
#include "features/CurveSampling.h"
#include "features/RuleSetQ.h"
#include "features/TangentCusps.h"
#include "features/TriangleSurfaceSharpEdges.h"
#include "features/UserPolylines.h"

namespace oraclemesh {

namespace {

// Curves leaving a vertex tangentially (TangentCusps.h): exact tangents within a degree are
// tangent (the presse's nut: 1e-7 degrees; part.step's line on an arc: 0.15), and one curve
// stands for both while the face between them is narrower than a quarter of the edge size.
constexpr double kTangentCuspAngleDeg = 1;
constexpr double kTangentCuspWidthPerEdgeSize = 0.25;

// The chord bound of the feature polylines: 0 (the default, featureSagittaTolerance) except
// for the thesis engine, whose polyline samples are all mesh vertices (thesisSagittaTolerance).
double thesisEngineSagitta(const JobSpec& job, const CriteriaTable& table, double edgeSize) {
  if (job.engine != Engine::Thesis) return 0;
  return thesisSagittaTolerance(edgeSize, table.strictest(&MaterialCriteria::facet_distance));
}

// How close the exact B-rep edges behind two polylines come (negative where either is no
// B-rep edge or OpenCASCADE cannot tell): the crossing split's check that chords which come
// close belong to curves that really meet.
double exactEdgeGap(const HierarchicalOracle& oracle, const FeaturePolyline& x, const FeaturePolyline& y) {
  if (x.source < 0 || x.edge < 0 || y.source < 0 || y.edge < 0) return -1;
  const BrepTopology* a = oracle.entries()[x.source].source->brepTopology();
  const BrepTopology* b = oracle.entries()[y.source].source->brepTopology();
  if (!a || !b) return -1;
  try {
    BRepExtrema_DistShapeShape extrema(a->edge(x.edge), b->edge(y.edge));
    return extrema.IsDone() ? extrema.Value() : -1;
  } catch (const Standard_Failure&) {
    return -1;
  }
}

// The point nearest to p of the B-rep edge polyline x samples; nullopt when x is no B-rep edge.
std::optional<Point3> exactEdgePoint(const HierarchicalOracle& oracle, const FeaturePolyline& x, const Point3& p) {
  if (x.source < 0 || x.edge < 0) return std::nullopt;
  const BrepTopology* topology = oracle.entries()[x.source].source->brepTopology();
  if (!topology) return std::nullopt;
  try {
    const BoundaryProjection q = topology->projectOnEdge(p, x.edge);
    if (!std::isfinite(q.distance)) return std::nullopt;
    return q.point;
  } catch (const Standard_Failure&) {
    return std::nullopt;
  } catch (const Error&) {
    return std::nullopt;
  }
}

FeatureGraph buildFeatures(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& table,
                           const RunControl& control, AssembledFeatures& assembled) {
  FeatureGraph all;
  if (!job.features) return all;
  const double edgeSize = table.strictest(&MaterialCriteria::edge_size);
  const double sagitta = thesisEngineSagitta(job, table, edgeSize);
  int nextCurve = 0;
  for (size_t i = 0; i < oracle.entries().size() && job.sharp_angle_deg > 0; ++i) {
    const Source& source = *oracle.entries()[i].source;
    std::function<double(const Point3&)> localEdgeSize;
    if (table.varies()) localEdgeSize = [&table](const Point3& p) { return table.edgeSizeAt(p); };
    FeatureGraph g;
    if (const auto* solid = source.brepTopology())
      g = extractSharpEdges(*solid, static_cast<int>(i), job.sharp_angle_deg, edgeSize, sagitta, localEdgeSize);
    else if (const auto* triangles = dynamic_cast<const TriangleSurface*>(&source))
      g = extractTriangleSurfaceSharpEdges(*triangles, static_cast<int>(i), job.sharp_angle_deg, edgeSize, localEdgeSize);
    for (FeaturePolyline& pl : g.polylines) {
      pl.curve = nextCurve++;  // extraction numbers per solid; the graph needs global ids
      all.polylines.push_back(std::move(pl));
    }
  }
  FeatureGraph clipped = clipToCompositeBoundary(all, oracle);
  // Where two inputs' boundaries cross (pin leaving the plate, cut faces across the plate).
  std::shared_ptr<const JunctionCurves> junctions;
  if (job.junctions) {
    junctions = std::make_shared<const JunctionCurves>(JunctionCurves::compute(oracle, job.sharp_angle_deg, &control));
    clipped = joinJunctions(clipped, junctions->polylines(edgeSize, sagitta), oracle, *junctions);
  }
  assembled.junctions = junctions;
  // Parts in contact along an arc sample it twice, a sagitta apart: those copies are one curve.
  const double curveSagitta = sagitta > 0 ? sagitta : featureSagittaTolerance(edgeSize, oracle.diagonal());
  clipped = removeCoincidentFeatures(clipped, oracle, 2 * curveSagitta);
  std::vector<std::shared_ptr<const UserCurve>> userCurves(job.user_polylines.size());
  for (size_t i = 0; i < job.user_polyline_curves.size() && i < userCurves.size(); ++i)
    if (!job.user_polyline_curves[i].empty())
      userCurves[i] = UserCurve::fromBrep(job.user_polyline_curves[i], "features.polylines[" + std::to_string(i) + "].brep");
  if (!job.user_polylines.empty()) {
    const FeatureGraph user = userPolylineFeatures(job.user_polylines, oracle, edgeSize, userCurves);
    clipped.polylines.insert(clipped.polylines.end(), user.polylines.begin(), user.polylines.end());
  }
  // Crossings become shared ends (thesis §3.2, the step before Rule Set Q of §3.2.1). Sharp
  // edges of different inputs can cross mid-segment (edges of two parts on a common plane), so
  // every graph is split, not only one with user curves.
  // User curves snap onto CAD chords within 2.5 % of the edge size (chords of curved CAD edges
  // are up to 2 % off the curve); two CAD curves cross where their chords come within twice
  // the sampling sagitta, but not within an edge size of an end they share (part.step has
  // curves leaving a vertex at under a degree). Chords of edges whose exact curves stay
  // farther apart than that 2.5 % never meet (Kurbelwelle.stp at the default size: two arcs
  // 0.2 mm apart on parallel planes, split at a point on neither, lost two subsegments).
  const size_t unsplit = clipped.polylines.size();
  clipped = splitAtCrossings(
      clipped, 0.025 * edgeSize, 2 * curveSagitta, edgeSize,
      [&oracle](const FeaturePolyline& x, const FeaturePolyline& y) { return exactEdgeGap(oracle, x, y); },
      [&oracle](const FeaturePolyline& curve, const Point3& p) { return exactEdgePoint(oracle, curve, p); });
  assembled.crossing_pieces = static_cast<int64_t>(clipped.polylines.size() - unsplit);
  // Where curves leave a vertex tangentially one stands for both near it (TangentCusps.h).
  std::function<double(const Point3&)> edgeSizeAt = [edgeSize](const Point3&) { return edgeSize; };
  if (table.varies()) edgeSizeAt = [&table](const Point3& p) { return table.edgeSizeAt(p); };
  clipped = mergeTangentCusps(
      clipped,
      [&oracle, &junctions](const FeaturePolyline& pl, bool atBack) {
        return leavingDirection(oracle, pl, junctions.get(), atBack);
      },
      edgeSizeAt, kTangentCuspAngleDeg, kTangentCuspWidthPerEdgeSize, &assembled.tangent_cusps);
  for (TangentCusp& cusp : assembled.tangent_cusps)
    if (cusp.source >= 0) cusp.input = oracle.entries()[cusp.source].source->name();
  // Ends are shared bitwise by construction; the tolerance only absorbs rounding.
  const std::vector<StarVertex> stars = findStarVertices(clipped, 1e-9 * oracle.diagonal());
  assembled.star_vertices = static_cast<int64_t>(stars.size());
  // The thesis engine applies Q1 itself (T1.1, with l_min,i of these polylines); equalising
  // here as well would make it split the already equalised segments again, at l_min,i / 9.
  if (job.engine != Engine::Thesis) clipped = equalizeStarSegments(clipped, stars);
  std::vector<std::shared_ptr<const std::vector<Point3>>> userPolylines;
  for (const std::vector<Point3>& polyline : job.user_polylines)
    userPolylines.push_back(std::make_shared<const std::vector<Point3>>(polyline));
  assembled.curves.addPolylines(clipped, junctions, userPolylines, userCurves);
  return clipped;
}

}  // namespace

AssembledFeatures assembleFeatures(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& criteria,
                                   const RunControl& control, std::vector<std::string>& warnings) {
  AssembledFeatures assembled(oracle);
  assembled.graph = buildFeatures(job, oracle, criteria, control, assembled);
  assembled.small_angles = findSmallInputAngles(oracle, assembled.graph, kSmallInputAngleLimitDeg, assembled.junctions.get());
  const std::vector<SmallInputAngle>& smallAngles = assembled.small_angles;
  if (!smallAngles.empty()) {
    const SmallInputAngle& worst = smallAngles.front();
    std::ostringstream message;
    message << smallAngles.size() << " input angle(s) under " << kSmallInputAngleLimitDeg << " degrees; the smallest is "
            << worst.angle_deg << " degrees (" << worst.kind << ") of input '" << worst.input << "' at ("
            << worst.location[0] << ", " << worst.location[1] << ", " << worst.location[2]
            << "): elements there can stay poor; see report.small_input_angles";
    warnings.push_back(message.str());
  }
  return assembled;
}

FeatureReport describeFeatures(const JobSpec& job, const AssembledFeatures& features) {
  FeatureReport report;
  for (const FeaturePolyline& pl : features.graph.polylines) {
    report.sharp_edge_polylines += pl.edge >= 0 || isTriangleSurfaceEdge(pl);
    report.junction_polylines += pl.junction >= 0;
    report.user_polylines += pl.user >= 0;
  }
  report.enabled = job.features;
  report.sharp_angle_deg = job.sharp_angle_deg;
  report.junctions = job.junctions;
  report.polylines = features.graph.polylines.size();
  report.crossing_pieces = features.crossing_pieces;
  report.star_vertices = features.star_vertices;
  report.tangent_cusps = features.tangent_cusps;
  return report;
}

}  // namespace oraclemesh
