#include "features/BrepSharpEdges.h"
#include "features/CurveSampling.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Curve2d.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <GCPnts_UniformAbscissa.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>

#include "Error.h"
#include "domain/OpenCascadeWork.h"
#include "domain/brep/OcctConversions.h"

namespace oraclemesh {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Sharp when the faces' normals differ by more than the threshold anywhere along the edge:
// a fillet that runs out tangentially at one end is still sharp where it is not tangent.
bool facesMeetSharply(const TopoDS_Edge& edge, const TopoDS_Face& a, const TopoDS_Face& b, double cosThreshold) {
  double first, last;
  BRep_Tool::Range(edge, first, last);
  constexpr int kSamples = 11;
  for (int i = 0; i < kSamples; ++i) {
    // Inset from the ends, where surfaces often degenerate (fillet ends, cone apexes).
    const double t = 0.0005 + 0.999 * i / (kSamples - 1);
    const double u = first + t * (last - first);
    gp_Vec na, nb;
    if (!outwardNormalAlongEdge(edge, a, u, na) || !outwardNormalAlongEdge(edge, b, u, nb)) continue;
    if (na.Dot(nb) < cosThreshold) return true;
  }
  return false;
}

// Narrow corners: where two sharp edges leave a common vertex at less than this angle
// (exact tangents), their polylines are refined near each other so that a chord strays from
// its curve by at most this fraction of the gap to the other curve, but not below the floor
// (relative to the diagonal). Curves leaving a vertex tangentially (part.step: 0 and 0.15
// degrees) are refined to the floor next to it, and the polyline angle Mesh_3 sees there
// shrinks with the floor: 1e-4 leaves no feature node of part.step off its curve at about the
// same meshing time; 1e-5 (0.45-degree polyline corners) made Mesh_3's exudation stall there.
constexpr double kNarrowCornerDeg = 15;
constexpr double kNarrowCornerGapFraction = 0.25;
constexpr double kNarrowCornerFloor = 1e-4;

// For every sharp edge with an end at a narrow corner, the other sharp edges of that corner.
// `corner` holds the point of each vertex of `vertexMap` (coincident vertices share one).
std::map<int, std::vector<int>> narrowCornerNeighbours(const BrepTopology& solid, const std::vector<int>& sharpEdges,
                                                       const TopTools_IndexedMapOfShape& vertexMap,
                                                       const std::vector<Point3>& corner) {
  struct End {
    int edge;
    gp_Vec leaving;  // unit tangent pointing away from the vertex along the edge
  };
  std::map<Point3, std::vector<End>> endsAt;
  for (int e : sharpEdges) {
    const TopoDS_Edge forward = TopoDS::Edge(solid.edge(e).Oriented(TopAbs_FORWARD));
    TopoDS_Vertex firstVertex, lastVertex;
    TopExp::Vertices(forward, firstVertex, lastVertex);
    if (firstVertex.IsNull() || lastVertex.IsNull()) continue;
    const BRepAdaptor_Curve curve(forward);
    gp_Vec tangent;
    if (unitTangent(curve, curve.FirstParameter(), tangent))
      endsAt[corner[vertexMap.FindIndex(firstVertex) - 1]].push_back({e, tangent});
    if (unitTangent(curve, curve.LastParameter(), tangent))
      endsAt[corner[vertexMap.FindIndex(lastVertex) - 1]].push_back({e, tangent.Reversed()});
  }
  const double cosNarrow = std::cos(kNarrowCornerDeg * kPi / 180);
  std::map<int, std::vector<int>> neighbours;
  for (const auto& [point, ends] : endsAt)
    for (size_t i = 0; i < ends.size(); ++i)
      for (size_t j = i + 1; j < ends.size(); ++j) {
        if (ends[i].edge == ends[j].edge || ends[i].leaving.Dot(ends[j].leaving) < cosNarrow) continue;
        neighbours[ends[i].edge].push_back(ends[j].edge);
        neighbours[ends[j].edge].push_back(ends[i].edge);
      }
  return neighbours;
}

}  // namespace

bool outwardNormalAt(const TopoDS_Face& face, const gp_Pnt& p, gp_Vec& normal) {
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
  if (surface.IsNull()) return false;
  GeomAPI_ProjectPointOnSurf projector(p, surface);
  if (!projector.IsDone() || projector.NbPoints() == 0) return false;
  double u, v;
  projector.LowerDistanceParameters(u, v);
  gp_Pnt q;
  gp_Vec du, dv;
  surface->D1(u, v, q, du, dv);
  normal = du.Crossed(dv);
  const double scale = du.Magnitude() * dv.Magnitude();
  if (!(scale > 0) || !(normal.Magnitude() > 1e-10 * scale)) return false;
  normal.Normalize();
  if (face.Orientation() == TopAbs_REVERSED) normal.Reverse();
  return true;
}

bool outwardNormalAlongEdge(const TopoDS_Edge& edge, const TopoDS_Face& face, double u, gp_Vec& normal) {
  BRepAdaptor_Curve2d pcurve(edge, face);
  const gp_Pnt2d uv = pcurve.Value(u);
  BRepAdaptor_Surface surface(face, Standard_False);
  gp_Pnt p;
  gp_Vec du, dv;
  surface.D1(uv.X(), uv.Y(), p, du, dv);
  normal = du.Crossed(dv);
  const double scale = du.Magnitude() * dv.Magnitude();
  if (!(normal.Magnitude() > 1e-10 * scale) || scale <= 0) return false;
  normal.Normalize();
  if (face.Orientation() == TopAbs_REVERSED) normal.Reverse();
  return true;
}

namespace {

// The corners merged within their tolerance must leave the polyline a path: no segment of
// length zero, and an edge that is not closed does not come back to its start. A vertex
// tolerance as long as its edge (a damaged file; ToleranceCheck refuses the widest), or a
// damaged coordinate far out that makes 1e-9 of the solid's size longer than its edges,
// would otherwise give a polyline that runs out and back, which neither engine can keep.
void requireDistinctPoints(const std::vector<Point3>& points, bool closed, const BrepTopology& solid, int edge,
                           double mergeDistance, double diagonal) {
  bool collapsed = !closed && points.front() == points.back();
  for (size_t i = 0; i + 1 < points.size() && !collapsed; ++i) collapsed = points[i] == points[i + 1];
  if (!collapsed) return;
  BRepAdaptor_Curve curve(solid.edge(edge));
  const Point3 a = toPoint3(curve.Value(curve.FirstParameter())), b = toPoint3(curve.Value(curve.LastParameter()));
  char text[480];
  std::snprintf(text, sizeof text,
                "': sharp edge %d (from (%g, %g, %g) to (%g, %g, %g)) collapses: corners closer than %g (the larger "
                "of their tolerance and 1e-9 of the solid's size, %g) are one point, which makes two of its points "
                "one; the file is damaged there (a tolerance or a coordinate): check it with Part > Check geometry, "
                "repair it or export it again from the CAD tool",
                edge + 1, a[0], a[1], a[2], b[0], b[1], b[2], mergeDistance, diagonal);
  throw InputError("input '" + solid.name() + text);
}

}  // namespace

FeatureGraph extractSharpEdges(const BrepTopology& solid, int sourceIndex, double sharpAngleDeg,
                               double maxSegmentLength, double sagittaTolerance,
                               const std::function<double(const Point3&)>& localSegmentLength) {
  if (!(maxSegmentLength > 0) || !std::isfinite(maxSegmentLength))
    throw InputError("input '" + solid.name() + "': the feature edge size must be a positive number (edge_size), got " +
                     std::to_string(maxSegmentLength));
  if (!(sharpAngleDeg >= 0 && sharpAngleDeg < 180))
    throw InputError("features.sharp_angle_deg must be between 0 and 180 degrees, got " + std::to_string(sharpAngleDeg));
  const double diagonal = solid.bbox().diagonal();
  const OpenCascadeWork working(solid.name());
  const double cosThreshold = std::cos(sharpAngleDeg * kPi / 180);
  if (!(sagittaTolerance > 0)) sagittaTolerance = featureSagittaTolerance(maxSegmentLength, diagonal);

  // One exact point per corner, shared by every polyline ending there (Mesh_3 finds corners
  // by bitwise-equal end points). Distinct vertices that coincide within their tolerance
  // (unsewn STEP topology) get the point of the first of them.
  TopTools_IndexedMapOfShape vertexMap;
  TopExp::MapShapes(solid.shape(), TopAbs_VERTEX, vertexMap);
  std::vector<Point3> corner(vertexMap.Extent());
  std::vector<double> cornerTolerance(vertexMap.Extent());
  for (int i = 0; i < vertexMap.Extent(); ++i) {
    const TopoDS_Vertex& v = TopoDS::Vertex(vertexMap(i + 1));
    corner[i] = toPoint3(BRep_Tool::Pnt(v));
    cornerTolerance[i] = std::max(BRep_Tool::Tolerance(v), 1e-9 * diagonal);
  }
  {
    std::vector<int> byX(corner.size());
    std::iota(byX.begin(), byX.end(), 0);
    std::stable_sort(byX.begin(), byX.end(), [&](int a, int b) { return corner[a][0] < corner[b][0]; });
    std::vector<Point3> original = corner;
    double maxTolerance = 0;
    for (double t : cornerTolerance) maxTolerance = std::max(maxTolerance, t);
    for (size_t i = 0; i < byX.size(); ++i)
      for (size_t j = i + 1; j < byX.size() && original[byX[j]][0] - original[byX[i]][0] <= maxTolerance; ++j) {
        const int a = std::min(byX[i], byX[j]), b = std::max(byX[i], byX[j]);
        if (distance(original[a], original[b]) <= std::min(cornerTolerance[a], cornerTolerance[b])) corner[b] = corner[a];
      }
  }

  FeatureGraph graph;
  try {
    std::vector<int> sharpEdges;
    for (int e = 0; e < solid.edgeCount(); ++e) {
      const TopoDS_Edge& edge = solid.edge(e);
      if (BRep_Tool::Degenerated(edge)) continue;
      const std::vector<int>& faces = solid.facesOfEdge(e);
      bool sharp = false;
      if (faces.size() == 1) {
        // A seam closes a periodic face onto itself; any other one-face edge is a free edge.
        sharp = !BRep_Tool::IsClosed(edge, solid.face(faces[0]));
      } else if (faces.size() == 2) {
        sharp = facesMeetSharply(edge, solid.face(faces[0]), solid.face(faces[1]), cosThreshold);
      } else {
        sharp = !faces.empty();  // non-manifold edge: always a feature
      }
      if (sharp) sharpEdges.push_back(e);
    }
    const std::map<int, std::vector<int>> narrow = narrowCornerNeighbours(solid, sharpEdges, vertexMap, corner);

    for (int e : sharpEdges) {
      const TopoDS_Edge& edge = solid.edge(e);
      const TopoDS_Edge forward = TopoDS::Edge(edge.Oriented(TopAbs_FORWARD));
      TopoDS_Vertex firstVertex, lastVertex;
      TopExp::Vertices(forward, firstVertex, lastVertex);
      if (firstVertex.IsNull() || lastVertex.IsNull()) continue;  // infinite edge: not in a solid
      const bool closed = firstVertex.IsSame(lastVertex);
      BRepAdaptor_Curve curve(forward);
      std::vector<double> params =
          localSegmentLength
              ? gradedPolylineParameters(
                    curve, curve.FirstParameter(), curve.LastParameter(),
                    [&](const gp_Pnt& p) { return localSegmentLength(toPoint3(p)); }, maxSegmentLength,
                    sagittaTolerance, closed ? 3 : 1)
              : polylineParameters(curve, curve.FirstParameter(), curve.LastParameter(), maxSegmentLength,
                                   sagittaTolerance, closed ? 3 : 1);
      const auto neighbours = narrow.find(e);
      if (neighbours != narrow.end()) {
        // Near a narrow corner the chords keep a fraction of the gap to the neighbouring
        // curves, down to the floor.
        auto gapTolerance = [&](const gp_Pnt& p) {
          double gap = std::numeric_limits<double>::infinity();
          for (int n : neighbours->second) gap = std::min(gap, solid.projectOnEdge(toPoint3(p), n).distance);
          return kNarrowCornerGapFraction * gap;
        };
        refineParameters(curve, params, gapTolerance, kNarrowCornerFloor * diagonal);
      }

      FeaturePolyline polyline;
      polyline.points.push_back(corner[vertexMap.FindIndex(firstVertex) - 1]);
      for (size_t i = 1; i + 1 < params.size(); ++i) polyline.points.push_back(toPoint3(curve.Value(params[i])));
      polyline.points.push_back(corner[vertexMap.FindIndex(lastVertex) - 1]);
      requireDistinctPoints(polyline.points, closed, solid, e,
                            std::max(cornerTolerance[vertexMap.FindIndex(firstVertex) - 1],
                                     cornerTolerance[vertexMap.FindIndex(lastVertex) - 1]),
                            diagonal);
      polyline.curve = sourceIndex * kCurvesPerSource + e;
      polyline.source = sourceIndex;
      polyline.edge = e;
      graph.polylines.push_back(std::move(polyline));
    }
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed while extracting the sharp edges of input '" + solid.name() + "' (" +
                failure.GetMessageString() + "): check the solid with Part > Check geometry");
  }
  return graph;
}

// ------------------------------------------------------------------------------------------

namespace {

class CompositeBoundaryClipper {
 public:
  explicit CompositeBoundaryClipper(const HierarchicalOracle& oracle)
      : oracle_(oracle), diagonal_(oracle.diagonal()), strictBand_(1e3 * oracle.tolerance()) {}

  void clip(const FeaturePolyline& polyline, std::vector<FeaturePolyline>& out);

 private:
  // Whether p, a point of a feature of entry `entry`, lies on the composite boundary.
  // "Inside a higher entry" means farther than strictBand_ inside, so that a feature lying on
  // another entry's surface is kept, not cut to pieces by rounding.
  bool onBoundary(const Point3& p, int entry) const;
  bool strictlyInside(const Source& s, const Point3& p) const {
    return s.bbox().contains(p) && s.inside(p) && s.project(p).distance > strictBand_;
  }
  static bool contains(const Source& s, const Point3& p) { return s.bbox().contains(p) && s.inside(p); }
  // The point of the polyline's curve for chord parameter t of segment a->b: on the exact
  // B-rep edge when the polyline is one.
  Point3 curvePoint(const Point3& a, const Point3& b, double t) const;
  Point3 onCurve(const Point3& p) const;
  // The cut point between chord parameters lo (state `loState`) and hi: bisection, then
  // refined onto the surface that causes the change.
  Point3 locateCut(const Point3& a, const Point3& b, double lo, double hi, bool loState, int entry) const;

  const HierarchicalOracle& oracle_;
  double diagonal_;
  double strictBand_;
  const BrepTopology* solid_ = nullptr;  // of the polyline being clipped, when it is a B-rep edge
  int edge_ = -1;
};

bool CompositeBoundaryClipper::onBoundary(const Point3& p, int entry) const {
  const auto& entries = oracle_.entries();
  for (int i = 0; i < entry; ++i)
    if (strictlyInside(*entries[i].source, p)) return false;
  // What lies beyond the entry's surface at p: the first lower entry that contains p.
  int below = -1;
  for (size_t j = entry + 1; j < entries.size(); ++j)
    if (contains(*entries[j].source, p)) {
      below = static_cast<int>(j);
      break;
    }
  const OracleEntry& self = entries[entry];
  if (self.role == Role::Cut) return below >= 0 && entries[below].role == Role::Material;
  if (below >= 0 && entries[below].role == Role::Material && entries[below].material == self.material)
    return !strictlyInside(*entries[below].source, p);
  return true;
}

Point3 CompositeBoundaryClipper::onCurve(const Point3& p) const {
  if (!solid_ || edge_ < 0) return p;
  const BoundaryProjection q = solid_->projectOnEdge(p, edge_);
  return std::isfinite(q.distance) ? q.point : p;
}

Point3 CompositeBoundaryClipper::curvePoint(const Point3& a, const Point3& b, double t) const {
  return onCurve(a + t * (b - a));
}

Point3 CompositeBoundaryClipper::locateCut(const Point3& a, const Point3& b, double lo, double hi, bool loState,
                                           int entry) const {
  const double segment = distance(a, b);
  const double resolution = 1e-12 * diagonal_;
  for (int i = 0; i < 200 && (hi - lo) * segment > resolution; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (onBoundary(curvePoint(a, b, mid), entry) == loState)
      lo = mid;
    else
      hi = mid;
  }
  Point3 cut = curvePoint(a, b, 0.5 * (lo + hi));

  // The bisection found where the curve enters or leaves the band of "strictly inside" of
  // one entry, a hair away from that entry's surface. A secant iteration on the signed
  // distance to that surface along the curve moves the cut onto the crossing itself, so that
  // the cut end lies on both the B-rep edge and the cutting surface within rounding.
  const Point3 pa = curvePoint(a, b, lo), pb = curvePoint(a, b, hi);
  const auto& entries = oracle_.entries();
  int crossed = -1, changes = 0;
  for (size_t j = 0; j < entries.size(); ++j) {
    if (static_cast<int>(j) == entry) continue;
    const Source& s = *entries[j].source;
    const bool changed = static_cast<int>(j) < entry ? strictlyInside(s, pa) != strictlyInside(s, pb)
                                                     : contains(s, pa) != contains(s, pb) ||
                                                           strictlyInside(s, pa) != strictlyInside(s, pb);
    if (changed) {
      crossed = static_cast<int>(j);
      ++changes;
    }
  }
  if (changes != 1 || !(segment > 0)) return cut;
  const Source& surface = *entries[crossed].source;
  auto signedDistance = [&](double t) {
    const Point3 x = curvePoint(a, b, t);
    const double d = surface.project(x).distance;
    return contains(surface, x) ? -d : d;
  };
  double t0 = 0.5 * (lo + hi), s0 = signedDistance(t0);
  double t1 = t0 + 2 * strictBand_ / segment, s1 = signedDistance(t1);
  double bestT = t0, bestGap = std::abs(s0);
  for (int i = 0; i < 40 && bestGap > 1e-15 * diagonal_ && s1 != s0; ++i) {
    const double t2 = t1 - s1 * (t1 - t0) / (s1 - s0);
    if (!std::isfinite(t2) || std::abs(t2 - 0.5 * (lo + hi)) * segment > 1e-4 * diagonal_) break;  // wandered off
    t0 = t1;
    s0 = s1;
    t1 = t2;
    s1 = signedDistance(t2);
    if (std::abs(s1) < bestGap) {
      bestGap = std::abs(s1);
      bestT = t1;
    }
  }
  return curvePoint(a, b, bestT);
}

void CompositeBoundaryClipper::clip(const FeaturePolyline& polyline, std::vector<FeaturePolyline>& out) {
  const int entry = polyline.source;
  const auto& entries = oracle_.entries();
  if (entry < 0 || entry >= static_cast<int>(entries.size()) || polyline.points.size() < 2) return;
  solid_ = entries[entry].source->brepTopology();
  edge_ = solid_ ? polyline.edge : -1;
  const double duplicate = 1e-9 * diagonal_;  // closer points are the same point
  const double shortest = 1e-6 * diagonal_;   // shorter pieces are dropped

  // Each segment is tested at a few points in between its ends too: a higher entry thinner
  // than a segment (a small pin) must still cut it.
  constexpr int kSubdivisions = 4;
  std::vector<FeaturePolyline> pieces;
  FeaturePolyline current;
  bool open = false;        // a piece is being collected
  bool startsAtFront = false;
  auto append = [&](const Point3& p, bool original) {
    if (!current.points.empty() && distance(current.points.back(), p) <= duplicate) {
      // An original polyline point (an exact B-rep vertex) wins over a nearby cut point.
      if (original) current.points.back() = p;
      return;
    }
    current.points.push_back(p);
  };
  auto closePiece = [&]() {
    if (open && current.points.size() >= 2) pieces.push_back(current);
    current.points.clear();
    open = false;
  };

  const std::vector<Point3>& pts = polyline.points;
  bool state = onBoundary(pts.front(), entry);
  if (state) {
    open = true;
    startsAtFront = true;
    append(pts.front(), true);
  }
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const Point3& a = pts[i];
    const Point3& b = pts[i + 1];
    double previousT = 0;
    for (int k = 1; k <= kSubdivisions; ++k) {
      const double t = static_cast<double>(k) / kSubdivisions;
      const bool next = k == kSubdivisions ? onBoundary(b, entry) : onBoundary(curvePoint(a, b, t), entry);
      if (next != state) {
        const Point3 cut = locateCut(a, b, previousT, t, state, entry);
        if (state) {
          append(cut, false);
          closePiece();
        } else {
          open = true;
          append(cut, false);
        }
        state = next;
      }
      previousT = t;
    }
    if (state) append(b, true);
  }
  const bool endsAtBack = state;
  closePiece();

  // A closed curve (circle with one vertex) cut somewhere: its piece through the start vertex
  // is one piece, not two meeting at a corner that is not one.
  const bool closedCurve = pts.front() == pts.back();
  if (closedCurve && pieces.size() >= 2 && startsAtFront && endsAtBack) {
    FeaturePolyline& last = pieces.back();
    const FeaturePolyline& firstPiece = pieces.front();
    last.points.insert(last.points.end(), firstPiece.points.begin() + 1, firstPiece.points.end());
    pieces.erase(pieces.begin());
  }

  for (FeaturePolyline& piece : pieces) {
    double length = 0;
    for (size_t i = 0; i + 1 < piece.points.size(); ++i) length += distance(piece.points[i], piece.points[i + 1]);
    if (length <= shortest) continue;
    piece.source = polyline.source;
    piece.edge = polyline.edge;
    out.push_back(std::move(piece));
  }
}

}  // namespace

FeatureGraph clipToCompositeBoundary(const FeatureGraph& graph, const HierarchicalOracle& oracle) {
  FeatureGraph clipped;
  CompositeBoundaryClipper clipper(oracle);
  try {
    for (const FeaturePolyline& polyline : graph.polylines) clipper.clip(polyline, clipped.polylines);
  } catch (const Standard_Failure& failure) {
    throw Error(std::string("OpenCASCADE failed while clipping feature edges to the composite boundary (") +
                failure.GetMessageString() + ")");
  }
  int nextCurve = 0;
  for (FeaturePolyline& polyline : clipped.polylines) polyline.curve = nextCurve++;
  return clipped;
}

}  // namespace oraclemesh
