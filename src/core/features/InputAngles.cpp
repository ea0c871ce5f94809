#include "features/InputAngles.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRep_Tool.hxx>
#include <ShapeAnalysis_Curve.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>
#include <utility>
#include <gp_Cone.hxx>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "Error.h"
#include "domain/BrepTopology.h"
#include "domain/TriangleSurface.h"
#include "domain/brep/OcctConversions.h"
#include "features/BrepSharpEdges.h"
#include "features/CurveSampling.h"

namespace oraclemesh {

namespace {

constexpr double kPi = 3.14159265358979323846;
double degrees(double radians) { return radians * 180 / kPi; }

// The edge as it is oriented in the face's wire: the face lies on the left of this direction
// when looking against the outward normal, which tells us which side of the edge is material.
bool edgeAsUsedByFace(const TopoDS_Face& face, const TopoDS_Edge& edge, TopoDS_Edge& oriented) {
  for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next())
    if (it.Current().IsSame(edge)) {
      oriented = TopoDS::Edge(it.Current());
      return true;
    }
  return false;
}

// Unit vector at curve parameter u, perpendicular to the edge in the face's tangent plane,
// pointing into the face. False where the face's normal is undefined.
bool intoFace(const TopoDS_Face& face, const TopoDS_Edge& edge, double u, gp_Vec& direction, gp_Vec& normal) {
  TopoDS_Edge oriented;
  if (!edgeAsUsedByFace(face, edge, oriented)) return false;
  if (!outwardNormalAlongEdge(edge, face, u, normal)) return false;
  BRepAdaptor_Curve curve(edge);
  gp_Pnt p;
  gp_Vec tangent;
  curve.D1(u, p, tangent);
  if (tangent.Magnitude() <= 0) return false;
  // Wires run counter-clockwise around the outward normal, so the face is at normal x tangent;
  // a REVERSED use runs against the curve's parametrisation.
  if (oriented.Orientation() == TopAbs_REVERSED) tangent.Reverse();
  direction = normal.Crossed(tangent);
  if (direction.Magnitude() <= 1e-12 * tangent.Magnitude()) return false;
  direction.Normalize();
  return true;
}

// Interior (material-side) angle between faces a and b along the edge at parameter u.
bool interiorDihedral(const TopoDS_Face& a, const TopoDS_Face& b, const TopoDS_Edge& edge, double u, double& angle) {
  gp_Vec intoA, intoB, normalA, normalB;
  if (!intoFace(a, edge, u, intoA, normalA) || !intoFace(b, edge, u, intoB, normalB)) return false;
  const double between = intoA.Angle(intoB);
  // Convex edge: going into face a leads away from face b's outward side.
  angle = intoA.Dot(normalB) <= 0 ? between : 2 * kPi - between;
  return true;
}

// Whether a point of entry `entry`'s boundary is on the composite boundary (not buried in a
// higher entry; for a cut, only where it removes material of a lower entry).
bool onCompositeBoundary(const HierarchicalOracle& oracle, const Point3& p, int entry) {
  if (oracle.coveredByHigherEntry(p, entry)) return false;
  const auto& entries = oracle.entries();
  if (entries[entry].role == Role::Material) return true;
  for (size_t j = entry + 1; j < entries.size(); ++j)
    if (entries[j].source->bbox().contains(p) && entries[j].source->inside(p))
      return entries[j].role == Role::Material;
  return false;
}

// A B-rep edge a feature curve comes from, as the angle measures along it need it.
struct FeatureBrepEdge {
  int entry;  // oracle entry of the solid
  int index;  // edge index in the solid
  const BrepTopology* solid;
  const TopoDS_Edge& edge;
  double first, last;  // parameter range
  const BRepAdaptor_Curve& curve;
};

// Measures each B-rep edge behind the feature curves once (`measure` returns the smallest
// angle it found along the edge, with its location; angle 360 for none) and adds the result
// under `kind` when it is under `limit`.
template <class Measure>
void measureFeatureBrepEdges(const HierarchicalOracle& oracle, const FeatureGraph& features, double limit,
                             const char* kind, std::vector<SmallInputAngle>& out, Measure measure) {
  std::set<std::pair<int, int>> edges;  // (oracle entry, edge index): curves may share an edge
  for (const FeaturePolyline& pl : features.polylines)
    if (pl.source >= 0 && pl.edge >= 0) edges.insert({pl.source, pl.edge});
  for (const auto& [entry, e] : edges) {
    const auto* solid = oracle.entries()[entry].source->brepTopology();
    if (!solid) continue;
    const TopoDS_Edge& edge = solid->edge(e);
    double first, last;
    BRep_Tool::Range(edge, first, last);
    const BRepAdaptor_Curve curve(edge);
    SmallInputAngle smallest = measure(FeatureBrepEdge{entry, e, solid, edge, first, last, curve});
    if (smallest.angle_deg >= limit) continue;
    smallest.kind = kind;
    smallest.input = solid->name();
    smallest.edge = e;
    out.push_back(std::move(smallest));
  }
}

void dihedralAngles(const HierarchicalOracle& oracle, const FeatureGraph& features, double limit,
                    std::vector<SmallInputAngle>& out) {
  measureFeatureBrepEdges(oracle, features, limit, "dihedral", out, [&](const FeatureBrepEdge& b) {
    SmallInputAngle smallest;
    smallest.angle_deg = 360;
    const std::vector<int>& faces = b.solid->facesOfEdge(b.index);
    if (faces.size() != 2) return smallest;
    constexpr int kSamples = 11;
    for (int i = 0; i < kSamples; ++i) {
      const double u = b.first + (0.0005 + 0.999 * i / (kSamples - 1)) * (b.last - b.first);
      double angle;
      if (!interiorDihedral(b.solid->face(faces[0]), b.solid->face(faces[1]), b.edge, u, angle)) continue;
      const Point3 p = toPoint3(b.curve.Value(u));
      if (degrees(angle) < smallest.angle_deg && onCompositeBoundary(oracle, p, b.entry)) {
        smallest.angle_deg = degrees(angle);
        smallest.location = p;
      }
    }
    return smallest;
  });
}

// Dihedral angles along a triangle surface's sharp edges (its polylines in `features`): for
// each polyline the smallest interior angle between the two triangles at any surface edge it
// runs along, on the composite boundary. A polyline's points are surface vertices and, between
// them, split points (TriangleSurfaceSharpEdges), so consecutive surface vertices on it are the
// ends of one surface edge.
void triangleSurfaceDihedrals(const HierarchicalOracle& oracle, const FeatureGraph& features, double limit,
                              std::vector<SmallInputAngle>& out) {
  for (size_t entry = 0; entry < oracle.entries().size(); ++entry) {
    const auto* surface = dynamic_cast<const TriangleSurface*>(oracle.entries()[entry].source.get());
    if (!surface) continue;
    std::vector<const FeaturePolyline*> lines;
    for (const FeaturePolyline& pl : features.polylines)
      if (isTriangleSurfaceEdge(pl) && pl.source == static_cast<int>(entry)) lines.push_back(&pl);
    if (lines.empty()) continue;
    std::vector<Point3> points;
    std::vector<std::array<int64_t, 3>> triangles;
    surface->outwardTriangles(points, triangles);
    std::map<Point3, int64_t> vertexAt;
    for (size_t v = 0; v < points.size(); ++v) vertexAt.emplace(points[v], static_cast<int64_t>(v));
    std::map<std::pair<int64_t, int64_t>, std::vector<size_t>> trianglesOfEdge;
    for (size_t t = 0; t < triangles.size(); ++t)
      for (int k = 0; k < 3; ++k)
        trianglesOfEdge[std::minmax(triangles[t][k], triangles[t][(k + 1) % 3])].push_back(t);
    // Interior angle at edge ab between triangles s and t, from their outward normals: the
    // edge is convex where t's third corner lies below s's plane.
    auto interior = [&](int64_t a, int64_t b, size_t s, size_t t) {
      auto normal = [&](size_t i) {
        const auto& c = triangles[i];
        return unit(cross(points[c[1]] - points[c[0]], points[c[2]] - points[c[0]]));
      };
      const Point3 ns = normal(s), nt = normal(t);
      const double between = std::atan2(norm(cross(ns, nt)), dot(ns, nt));
      int64_t apex = -1;
      for (int64_t x : triangles[t])
        if (x != a && x != b) apex = x;
      return dot(points[apex] - points[a], ns) <= 0 ? kPi - between : kPi + between;
    };
    for (const FeaturePolyline* pl : lines) {
      SmallInputAngle smallest;
      smallest.angle_deg = 360;
      int64_t previous = -1;
      for (const Point3& p : pl->points) {
        const auto found = vertexAt.find(p);
        if (found == vertexAt.end()) continue;  // a split point
        const int64_t v = found->second;
        if (previous >= 0) {
          const auto at = trianglesOfEdge.find(std::minmax(previous, v));
          if (at != trianglesOfEdge.end() && at->second.size() == 2) {
            const double angle = degrees(interior(previous, v, at->second[0], at->second[1]));
            const Point3 middle = 0.5 * (points[previous] + points[v]);
            if (angle < smallest.angle_deg && onCompositeBoundary(oracle, middle, static_cast<int>(entry))) {
              smallest.angle_deg = angle;
              smallest.location = middle;
            }
          }
        }
        previous = v;
      }
      if (smallest.angle_deg >= limit) continue;
      smallest.kind = "dihedral";
      smallest.input = surface->name();
      smallest.curve = pl->curve;
      out.push_back(smallest);
    }
  }
}

}  // namespace

Point3 leavingDirection(const HierarchicalOracle& oracle, const FeaturePolyline& pl, const JunctionCurves* junctions,
                        bool atBack) {
  const size_t n = pl.points.size();
  const Point3& end = atBack ? pl.points[n - 1] : pl.points[0];
  const Point3 segment = atBack ? pl.points[n - 2] - pl.points[n - 1] : pl.points[1] - pl.points[0];
  const Point3 chord = (1 / norm(segment)) * segment;
  std::vector<gp_Vec> candidates;
  if (pl.source >= 0 && pl.edge >= 0) {
    if (const auto* solid = oracle.entries()[pl.source].source->brepTopology()) {
      const BRepAdaptor_Curve curve(solid->edge(pl.edge));
      // The end's parameter, and either end of the curve where the point is on it (a closed
      // edge's vertex is at both).
      const gp_Pnt p(end[0], end[1], end[2]);
      const double tolerance = 1e-7 * oracle.diagonal();
      gp_Pnt projected;
      double u = curve.FirstParameter();
      std::vector<double> params;
      if (ShapeAnalysis_Curve().Project(curve, p, tolerance, projected, u) <= tolerance) params.push_back(u);
      for (double curveEnd : {curve.FirstParameter(), curve.LastParameter()})
        if (curve.Value(curveEnd).Distance(p) <= tolerance) params.push_back(curveEnd);
      gp_Vec tangent;
      for (double param : params)
        if (unitTangent(curve, param, tangent)) candidates.push_back(tangent);
    }
  } else if (pl.junction >= 0 && junctions) {
    const auto [entryA, entryB] = junctions->entries(pl.junction);
    const auto [faceA, faceB] = junctions->faces(pl.junction);
    const auto* solidA = oracle.entries()[entryA].source->brepTopology();
    const auto* solidB = oracle.entries()[entryB].source->brepTopology();
    gp_Vec normalA, normalB;
    const gp_Pnt p(end[0], end[1], end[2]);
    if (solidA && solidB && outwardNormalAt(solidA->face(faceA), p, normalA) &&
        outwardNormalAt(solidB->face(faceB), p, normalB)) {
      const gp_Vec tangent = normalA.Crossed(normalB);
      if (tangent.Magnitude() > 1e-6) candidates.push_back(tangent.Normalized());
    }
  }
  // The candidate (signed to run into the polyline) closest to the end segment: a closed
  // edge that is not smooth at its vertex has different tangents at its two ends.
  Point3 best = chord;
  double bestAlignment = -2;
  for (const gp_Vec& t : candidates) {
    Point3 direction{t.X(), t.Y(), t.Z()};
    if (dot(direction, chord) < 0) direction = -1.0 * direction;
    if (dot(direction, chord) > bestAlignment) {
      bestAlignment = dot(direction, chord);
      best = direction;
    }
  }
  return best;
}

namespace {

void curveAngles(const HierarchicalOracle& oracle, const FeatureGraph& features, const JunctionCurves* junctions,
                 double limit, std::vector<SmallInputAngle>& out) {
  // Feature curves meet at bitwise-equal end points (extraction and clipping guarantee it).
  struct End {
    Point3 leaving;  // unit tangent of the curve, pointing away from the vertex
    int source;
  };
  std::map<Point3, std::vector<End>> ends;
  for (const FeaturePolyline& pl : features.polylines) {
    const size_t n = pl.points.size();
    if (n < 2) continue;
    if (distance(pl.points[0], pl.points[1]) > 0)
      ends[pl.points[0]].push_back({leavingDirection(oracle, pl, junctions, false), pl.source});
    if (distance(pl.points[n - 1], pl.points[n - 2]) > 0)
      ends[pl.points[n - 1]].push_back({leavingDirection(oracle, pl, junctions, true), pl.source});
  }
  auto inputName = [&](int source) {
    return source >= 0 ? oracle.entries()[source].source->name() : std::string("junction");
  };
  for (const auto& [vertex, list] : ends)
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j) {
        // atan2 keeps angles of a fraction of a degree accurate (acos loses half the digits).
        const double angle =
            degrees(std::atan2(norm(cross(list[i].leaving, list[j].leaving)), dot(list[i].leaving, list[j].leaving)));
        if (angle >= limit) continue;
        SmallInputAngle a;
        a.kind = "curves";
        a.angle_deg = angle;
        a.location = vertex;
        a.input = inputName(list[i].source);
        if (list[j].source != list[i].source) a.input += " / " + inputName(list[j].source);
        out.push_back(a);
      }
}

void coneApexes(const HierarchicalOracle& oracle, double limit, std::vector<SmallInputAngle>& out) {
  for (size_t entry = 0; entry < oracle.entries().size(); ++entry) {
    const auto* solid = oracle.entries()[entry].source->brepTopology();
    if (!solid) continue;
    const double tolerance = 1e-7 * solid->bbox().diagonal();
    for (int f = 0; f < solid->faceCount(); ++f) {
      const TopoDS_Face& face = solid->face(f);
      BRepAdaptor_Surface surface(face, Standard_False);
      if (surface.GetType() != GeomAbs_Cone) continue;
      const gp_Cone cone = surface.Cone();
      const Point3 apex = toPoint3(cone.Apex());
      // Only a cone that reaches its apex has a tip; a frustum has none.
      bool reachesApex = false;
      for (TopExp_Explorer it(face, TopAbs_VERTEX); it.More() && !reachesApex; it.Next())
        reachesApex = distance(toPoint3(BRep_Tool::Pnt(TopoDS::Vertex(it.Current()))), apex) <= tolerance;
      const double opening = 2 * degrees(std::abs(cone.SemiAngle()));
      if (!reachesApex || opening >= limit || !onCompositeBoundary(oracle, apex, static_cast<int>(entry))) continue;
      SmallInputAngle a;
      a.kind = "cone_apex";
      a.angle_deg = opening;
      a.location = apex;
      a.input = solid->name();
      out.push_back(a);
    }
  }
}

// The smallest composite material wedge at point p of a junction between faces a and b: the
// two faces' traces in the plane normal to the curve bound four sectors, each labelled by the
// oracle at its bisector (1e-4 of the diagonal out); runs of one material are its wedges.
// Negative when the faces are tangent there or a normal is undefined.
double smallestMaterialWedge(const HierarchicalOracle& oracle, const TopoDS_Face& a, const TopoDS_Face& b,
                             const Point3& p) {
  gp_Vec na, nb;
  const gp_Pnt at(p[0], p[1], p[2]);
  if (!outwardNormalAt(a, at, na) || !outwardNormalAt(b, at, nb)) return -1;
  const Point3 normalA{na.X(), na.Y(), na.Z()}, normalB{nb.X(), nb.Y(), nb.Z()};
  Point3 tangent = cross(normalA, normalB);  // the curve runs along both faces
  if (norm(tangent) < 1e-6) return -1;
  tangent = (1 / norm(tangent)) * tangent;
  const Point3 e1 = cross(tangent, normalA), e2 = cross(tangent, e1);  // unit: normals are unit
  const Point3 traceB = cross(tangent, normalB);
  std::vector<double> rays = {0, kPi, std::atan2(dot(traceB, e2), dot(traceB, e1))};
  rays.push_back(rays[2] + kPi);
  for (double& r : rays) r = std::fmod(r + 4 * kPi, 2 * kPi);
  std::sort(rays.begin(), rays.end());
  const double radius = 1e-4 * oracle.diagonal();
  std::vector<double> sector(4);
  std::vector<int> label(4);
  for (int k = 0; k < 4; ++k) {
    const double from = rays[k], to = k == 3 ? rays[0] + 2 * kPi : rays[k + 1];
    sector[k] = to - from;
    const double middle = 0.5 * (from + to);
    label[k] = oracle.label(p + radius * (std::cos(middle) * e1 + std::sin(middle) * e2));
  }
  // Start at a change of label so that runs do not wrap around.
  int start = 0;
  while (start < 4 && label[start] == label[(start + 3) % 4]) ++start;
  if (start == 4) return -1;  // one label all round: not on the composite boundary
  double smallest = -1, run = 0;
  for (int i = 0; i < 4; ++i) {
    const int k = (start + i) % 4;
    run += sector[k];
    if (label[k] != label[(k + 1) % 4]) {
      if (label[k] > 0 && (smallest < 0 || run < smallest)) smallest = run;
      run = 0;
    }
  }
  return smallest;
}

void junctionAngles(const HierarchicalOracle& oracle, const FeatureGraph& features, const JunctionCurves& junctions,
                    double limit, std::vector<SmallInputAngle>& out) {
  std::map<int, std::vector<const FeaturePolyline*>> byJunction;
  for (const FeaturePolyline& pl : features.polylines)
    if (pl.junction >= 0) byJunction[pl.junction].push_back(&pl);
  for (const auto& [junction, polylines] : byJunction) {
    const auto [entryA, entryB] = junctions.entries(junction);
    const auto [faceA, faceB] = junctions.faces(junction);
    const auto* solidA = oracle.entries()[entryA].source->brepTopology();
    const auto* solidB = oracle.entries()[entryB].source->brepTopology();
    if (!solidA || !solidB) continue;
    SmallInputAngle smallest;
    smallest.angle_deg = 360;
    for (const FeaturePolyline* pl : polylines) {
      // Inner points lie on the exact curve; the ends may be where a third surface cuts in.
      std::vector<Point3> samples(pl->points.begin() + 1, pl->points.end() - 1);
      if (samples.empty()) samples.push_back(junctions.projectOnCurve(junction, 0.5 * (pl->points[0] + pl->points[1])).point);
      for (const Point3& p : samples) {
        const double wedge = smallestMaterialWedge(oracle, solidA->face(faceA), solidB->face(faceB), p);
        if (wedge >= 0 && degrees(wedge) < smallest.angle_deg) {
          smallest.angle_deg = degrees(wedge);
          smallest.location = p;
        }
      }
    }
    if (smallest.angle_deg < limit) {
      smallest.kind = "junction";
      smallest.input = solidA->name() + " / " + solidB->name();
      out.push_back(smallest);
    }
  }
}

// Composite wedges along the sharp B-rep edges in `features` where another input's boundary
// passes through the edge: a part resting on a chamfered nut covers the chamfer's upper edge,
// and the gap between its flat face and the chamfer is an outside wedge that the single-solid
// dihedral angle does not see (presse_asm.step: about 30 degrees along the nut's 32 mm circle).
// Such curves get the terminator rules of small dihedral angles. At samples of the edge that
// lie on another input's boundary (within ten times the oracle tolerance), the labels of
// kProbes points on a small circle in the plane normal to the edge give the sectors; three or
// more runs of labels mean that other inputs take part, and the shortest run is the wedge.
void contactWedges(const HierarchicalOracle& oracle, const FeatureGraph& features, double limit,
                   std::vector<SmallInputAngle>& out) {
  const auto& entries = oracle.entries();
  const double radius = 1e-4 * oracle.diagonal();
  constexpr int kProbes = 72, kSamples = 5;
  measureFeatureBrepEdges(oracle, features, limit, "contact", out, [&](const FeatureBrepEdge& b) {
    SmallInputAngle smallest;
    smallest.angle_deg = 360;
    for (int i = 0; i < kSamples; ++i) {
      const double u = b.first + (i + 0.5) / kSamples * (b.last - b.first);
      gp_Pnt at;
      gp_Vec d1;
      b.curve.D1(u, at, d1);
      const Point3 p = toPoint3(at);
      bool touched = false;  // another input's boundary passes through the edge here
      for (size_t j = 0; j < entries.size() && !touched; ++j)
        touched = static_cast<int>(j) != b.entry && entries[j].source->bbox().contains(p, radius) &&
                  entries[j].source->project(p).distance <= 10 * oracle.tolerance();
      if (!touched || d1.Magnitude() <= 0) continue;
      Point3 tangent{d1.X(), d1.Y(), d1.Z()};
      tangent = (1 / norm(tangent)) * tangent;
      // Any unit vector across the tangent, then the third axis.
      Point3 e1 = cross(tangent, std::abs(tangent[0]) < 0.9 ? Point3{1, 0, 0} : Point3{0, 1, 0});
      e1 = (1 / norm(e1)) * e1;
      const Point3 e2 = cross(tangent, e1);
      std::array<int, kProbes> label;
      for (int k = 0; k < kProbes; ++k) {
        const double angle = 2 * kPi * k / kProbes;
        label[k] = oracle.label(p + radius * (std::cos(angle) * e1 + std::sin(angle) * e2));
      }
      int start = 0;  // a change of label, so that runs do not wrap around
      while (start < kProbes && label[start] == label[(start + kProbes - 1) % kProbes]) ++start;
      if (start == kProbes) continue;
      std::vector<int> runs;
      int run = 0;
      for (int k = 0; k < kProbes; ++k) {
        const int at_k = (start + k) % kProbes;
        ++run;
        if (label[at_k] != label[(at_k + 1) % kProbes]) runs.push_back(run), run = 0;
      }
      if (runs.size() < 3) continue;
      const double wedge = 360.0 * *std::min_element(runs.begin(), runs.end()) / kProbes;
      if (wedge < smallest.angle_deg) {
        smallest.angle_deg = wedge;
        smallest.location = p;
      }
    }
    return smallest;
  });
}

}  // namespace

std::vector<SmallInputAngle> findSmallInputAngles(const HierarchicalOracle& oracle, const FeatureGraph& features,
                                                  double limitDeg, const JunctionCurves* junctions) {
  std::vector<SmallInputAngle> result;
  try {
    dihedralAngles(oracle, features, limitDeg, result);
    triangleSurfaceDihedrals(oracle, features, limitDeg, result);
    curveAngles(oracle, features, junctions, limitDeg, result);
    coneApexes(oracle, limitDeg, result);
    if (junctions) junctionAngles(oracle, features, *junctions, limitDeg, result);
    contactWedges(oracle, features, limitDeg, result);
  } catch (const Standard_Failure& failure) {
    throw Error(std::string("OpenCASCADE failed while measuring the input angles (") + failure.GetMessageString() +
                "): check the solids with Part > Check geometry");
  }
  std::stable_sort(result.begin(), result.end(),
                   [](const SmallInputAngle& a, const SmallInputAngle& b) { return a.angle_deg < b.angle_deg; });
  return result;
}

}  // namespace oraclemesh
