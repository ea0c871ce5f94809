#include "features/JunctionCurves.h"
#include "features/CurveSampling.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAlgoAPI_Section.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Tool.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <GCPnts_UniformAbscissa.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "Error.h"
#include "domain/BrepTopology.h"
#include "domain/brep/OcctConversions.h"
#include "features/BrepSharpEdges.h"

namespace oraclemesh {

namespace {

constexpr double kPi = 3.14159265358979323846;

Point3 normalized(const Point3& v) {
  const double n = norm(v);
  return n > 0 ? (1 / n) * v : v;
}

struct Junction {
  TopoDS_Edge edge;  // FORWARD-oriented section edge
  int entryA = -1, entryB = -1;  // entryA < entryB
  int faceA = -1, faceB = -1;
  bool closed = false;
  Point3 firstPoint{}, lastPoint{};  // the section vertices
  std::vector<std::pair<double, double>> kept;  // curve parameter intervals, increasing
};

// Decides, along one section edge, where it is a crease of the composite boundary.
class CreaseClassifier {
 public:
  CreaseClassifier(const HierarchicalOracle& oracle, const Junction& j, double creaseAngleRad)
      : oracle_(oracle),
        junction_(j),
        curve_(j.edge),
        radius_(1e-4 * oracle.diagonal()),
        creaseAngle_(creaseAngleRad) {
    const auto& entries = oracle.entries();
    solidA_ = entries[j.entryA].source->brepTopology();
    solidB_ = entries[j.entryB].source->brepTopology();
  }

  const BRepAdaptor_Curve& curve() const { return curve_; }
  Point3 at(double t) const { return toPoint3(curve_.Value(t)); }

  // Whether the curve point at parameter t is a crease of the composite boundary.
  bool crease(double t) const {
    gp_Pnt p;
    gp_Vec d1;
    curve_.D1(t, p, d1);
    if (!(d1.Magnitude() > 0)) return false;
    const Point3 c = toPoint3(p);
    const Point3 tangent = normalized(toPoint3(d1));
    // Directions of the two faces' traces in the normal plane: the ring samples the four
    // wedges between them at their bisectors, so a thin wedge is never missed.
    std::vector<Point3> traces;
    gp_Vec na, nb;
    if (outwardNormalAt(solidA_->face(junction_.faceA), p, na)) traces.push_back(normalized(cross(tangent, toPoint3(na))));
    if (outwardNormalAt(solidB_->face(junction_.faceB), p, nb)) traces.push_back(normalized(cross(tangent, toPoint3(nb))));
    Point3 e1 = traces.empty() ? Point3{0, 0, 0} : traces.front();
    if (norm(e1) < 0.5) {
      const int axis = std::abs(tangent[0]) < 0.6 ? 0 : (std::abs(tangent[1]) < 0.6 ? 1 : 2);
      Point3 helper{0, 0, 0};
      helper[axis] = 1;
      e1 = normalized(cross(tangent, helper));
    }
    const Point3 e2 = cross(tangent, e1);
    auto ringPoint = [&](double angle) { return c + radius_ * (std::cos(angle) * e1 + std::sin(angle) * e2); };
    auto angleOf = [&](const Point3& d) {
      const double a = std::atan2(dot(d, e2), dot(d, e1));
      return a < 0 ? a + 2 * kPi : a;
    };

    std::vector<double> angles;
    constexpr int kRing = 16;
    for (int k = 0; k < kRing; ++k) angles.push_back(2 * kPi * (k + 0.3711) / kRing);
    if (traces.size() == 2 && norm(cross(traces[0], traces[1])) > 1e-6)
      for (double sa : {1.0, -1.0})
        for (double sb : {1.0, -1.0}) angles.push_back(angleOf(normalized(sa * traces[0] + sb * traces[1])));
    std::sort(angles.begin(), angles.end());
    std::vector<int> labels;
    for (double a : angles) labels.push_back(oracle_.label(ringPoint(a)));
    const size_t n = angles.size();
    std::vector<size_t> changes;  // change between sample k and k + 1 (cyclic)
    for (size_t k = 0; k < n; ++k)
      if (labels[k] != labels[(k + 1) % n]) changes.push_back(k);
    if (changes.empty()) return false;  // not on the composite boundary
    if (changes.size() >= 3) return true;  // three regions meet, or a non-manifold crossing
    // Two changes: the composite boundary is two half-surfaces; flat means no crease.
    double at[2];
    for (int m = 0; m < 2; ++m) {
      const size_t k = changes[m];
      double lo = angles[k], hi = angles[(k + 1) % n];
      if (hi <= lo) hi += 2 * kPi;
      const int loLabel = labels[k];
      for (int i = 0; i < 14; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (oracle_.label(ringPoint(mid)) == loLabel)
          lo = mid;
        else
          hi = mid;
      }
      at[m] = 0.5 * (lo + hi);
    }
    double wedge = std::fmod(std::abs(at[1] - at[0]), 2 * kPi);
    wedge = std::min(wedge, 2 * kPi - wedge);
    return kPi - wedge > creaseAngle_;
  }

  // The parameter in (lo, hi) where the crease state changes from `loState`: on the surface
  // of the one other entry whose inside changes there when there is one (bisection, then
  // regula falsi on its signed distance), else where the ring's answer changes.
  double locateChange(double lo, double hi, bool loState) const {
    const auto& entries = oracle_.entries();
    const Point3 pLo = at(lo), pHi = at(hi);
    int crossing = -1, count = 0;
    for (size_t e = 0; e < entries.size(); ++e) {
      if (static_cast<int>(e) == junction_.entryA || static_cast<int>(e) == junction_.entryB) continue;
      if (contains(*entries[e].source, pLo) != contains(*entries[e].source, pHi)) {
        crossing = static_cast<int>(e);
        ++count;
      }
    }
    const double resolution = 1e-13 * oracle_.diagonal();
    if (count == 1) {
      const Source& s = *entries[crossing].source;
      auto f = [&](double t) {
        const Point3 x = at(t);
        const double d = s.project(x).distance;
        return contains(s, x) ? -d : d;
      };
      double a = lo, b = hi, fa = f(a), fb = f(b);
      if (std::isfinite(fa) && std::isfinite(fb) && (fa <= 0) != (fb <= 0)) {
        int side = 0;
        double best = std::abs(fa) < std::abs(fb) ? a : b, bestF = std::min(std::abs(fa), std::abs(fb));
        for (int i = 0; i < 100 && bestF > resolution; ++i) {
          double t = (a * fb - b * fa) / (fb - fa);  // Illinois regula falsi
          if (!(t > std::min(a, b) && t < std::max(a, b))) t = 0.5 * (a + b);
          const double ft = f(t);
          if (!std::isfinite(ft)) break;
          if (std::abs(ft) < bestF) {
            bestF = std::abs(ft);
            best = t;
          }
          if ((ft <= 0) == (fb <= 0)) {
            b = t;
            fb = ft;
            if (side == -1) fa *= 0.5;
            side = -1;
          } else {
            a = t;
            fa = ft;
            if (side == 1) fb *= 0.5;
            side = 1;
          }
          if (std::abs(b - a) * std::max(1.0, curveSpeed(t)) < resolution) break;
        }
        return best;
      }
    }
    for (int i = 0; i < 200 && distance(at(lo), at(hi)) > 1e-12 * oracle_.diagonal(); ++i) {
      const double mid = 0.5 * (lo + hi);
      if (crease(mid) == loState)
        lo = mid;
      else
        hi = mid;
    }
    return 0.5 * (lo + hi);
  }

 private:
  static bool contains(const Source& s, const Point3& p) { return s.bbox().contains(p) && s.inside(p); }
  double curveSpeed(double t) const {
    gp_Pnt p;
    gp_Vec d1;
    curve_.D1(t, p, d1);
    return d1.Magnitude();
  }

  const HierarchicalOracle& oracle_;
  const Junction& junction_;
  BRepAdaptor_Curve curve_;
  const BrepTopology* solidA_ = nullptr;
  const BrepTopology* solidB_ = nullptr;
  double radius_;
  double creaseAngle_;
};

int faceIndex(const BrepTopology& solid, const TopoDS_Shape& face) {
  for (int f = 0; f < solid.faceCount(); ++f)
    if (solid.face(f).IsSame(face)) return f;
  return -1;
}

// The kept parameter intervals of one section edge.
void classify(const HierarchicalOracle& oracle, Junction& j, double creaseAngleRad, const RunControl* control) {
  CreaseClassifier classifier(oracle, j, creaseAngleRad);
  const BRepAdaptor_Curve& curve = classifier.curve();
  const double first = curve.FirstParameter(), last = curve.LastParameter();
  const double diagonal = oracle.diagonal();
  const double length = GCPnts_AbscissaPoint::Length(curve, first, last);
  const int samples = std::clamp(static_cast<int>(std::ceil(length / (diagonal / 100))), 8, 400);
  std::vector<double> t(samples + 1);
  {
    GCPnts_UniformAbscissa uniform(curve, samples + 1, first, last);
    for (int i = 0; i <= samples; ++i)
      t[i] = uniform.IsDone() && uniform.NbPoints() == samples + 1 ? uniform.Parameter(i + 1)
                                                                    : first + (last - first) * i / samples;
    t.front() = first;
    t.back() = last;
  }
  // An end is judged a little inside: at the very end a third face of an input meets the
  // curve and the ring would see that corner, not the curve.
  const double inset = std::min(1e-3 * diagonal, 0.25 * length / samples);
  std::vector<double> probe = t;
  probe.front() = GCPnts_AbscissaPoint(curve, inset, first).Parameter();
  probe.back() = GCPnts_AbscissaPoint(curve, -inset, last).Parameter();
  std::vector<char> state(probe.size());
  for (size_t i = 0; i < probe.size(); ++i) {
    if (control && (i & 15) == 0) control->checkpoint();
    state[i] = classifier.crease(probe[i]);
  }
  bool open = state[0];
  double start = first;
  for (size_t i = 0; i + 1 < probe.size(); ++i) {
    if (state[i + 1] == state[i]) continue;
    const double cut = classifier.locateChange(probe[i], probe[i + 1], state[i]);
    if (state[i]) {
      j.kept.emplace_back(start, cut);
      open = false;
    } else {
      start = cut;
      open = true;
    }
  }
  if (open) j.kept.emplace_back(start, last);
  // Drop pieces too short to matter.
  std::vector<std::pair<double, double>> kept;
  for (const auto& [a, b] : j.kept)
    if (GCPnts_AbscissaPoint::Length(curve, a, b) > 1e-6 * diagonal) kept.emplace_back(a, b);
  j.kept = std::move(kept);
}

}  // namespace

struct JunctionCurves::Impl {
  std::vector<Junction> junctions;
  double diagonal = 0;
};

JunctionCurves::JunctionCurves() : impl_(std::make_unique<Impl>()) {}
JunctionCurves::~JunctionCurves() = default;
JunctionCurves::JunctionCurves(JunctionCurves&&) noexcept = default;
JunctionCurves& JunctionCurves::operator=(JunctionCurves&&) noexcept = default;

size_t JunctionCurves::size() const { return impl_->junctions.size(); }
std::pair<int, int> JunctionCurves::entries(int junction) const {
  const Junction& j = impl_->junctions.at(junction);
  return {j.entryA, j.entryB};
}
std::pair<int, int> JunctionCurves::faces(int junction) const {
  const Junction& j = impl_->junctions.at(junction);
  return {j.faceA, j.faceB};
}

JunctionCurves JunctionCurves::compute(const HierarchicalOracle& oracle, double creaseAngleDeg,
                                       const RunControl* control) {
  JunctionCurves result;
  Impl& m = *result.impl_;
  m.diagonal = oracle.diagonal();
  const double creaseAngle = creaseAngleDeg * kPi / 180;
  const double tangentSine = std::sin(1.0 * kPi / 180);  // faces within 1 degree: tangent
  const auto& entries = oracle.entries();
  const double margin = oracle.tolerance();
  try {
    for (size_t a = 0; a < entries.size(); ++a) {
      const auto* solidA = entries[a].source->brepTopology();
      if (!solidA) continue;
      for (size_t b = a + 1; b < entries.size(); ++b) {
        const auto* solidB = entries[b].source->brepTopology();
        if (!solidB) continue;
        const Bbox ba = solidA->bbox(), bb = solidB->bbox();
        bool overlap = true;
        for (int k = 0; k < 3; ++k)
          overlap = overlap && ba.min[k] <= bb.max[k] + margin && bb.min[k] <= ba.max[k] + margin;
        if (!overlap) continue;
        // Two cuts never make a crease of the composite boundary between themselves alone,
        // but they may where material lies beyond: the ring decides, as for any pair.
        if (control) control->checkpoint();
        BRepAlgoAPI_Section section(solidA->shape(), solidB->shape(), Standard_False);
        section.Approximation(Standard_True);
        section.Build();
        if (!section.IsDone()) {
          throw Error("OpenCASCADE could not intersect the boundaries of inputs '" + solidA->name() + "' and '" +
                      solidB->name() + "': check both with Part > Check geometry");
        }
        for (TopExp_Explorer ex(section.Shape(), TopAbs_EDGE); ex.More(); ex.Next()) {
          const TopoDS_Edge edge = TopoDS::Edge(ex.Current().Oriented(TopAbs_FORWARD));
          if (BRep_Tool::Degenerated(edge)) continue;
          TopoDS_Shape fa, fb;
          // An edge without a face on both sides is an edge of one input lying on the other:
          // it is that input's own edge (a sharp-edge feature when sharp).
          if (!section.HasAncestorFaceOn1(edge, fa) || !section.HasAncestorFaceOn2(edge, fb)) continue;
          Junction j;
          j.edge = edge;
          j.entryA = static_cast<int>(a);
          j.entryB = static_cast<int>(b);
          j.faceA = faceIndex(*solidA, fa);
          j.faceB = faceIndex(*solidB, fb);
          if (j.faceA < 0 || j.faceB < 0) continue;
          TopoDS_Vertex v0, v1;
          TopExp::Vertices(edge, v0, v1);
          if (v0.IsNull() || v1.IsNull()) continue;
          j.closed = v0.IsSame(v1);
          j.firstPoint = toPoint3(BRep_Tool::Pnt(v0));
          j.lastPoint = j.closed ? j.firstPoint : toPoint3(BRep_Tool::Pnt(v1));
          BRepAdaptor_Curve curve(edge);
          if (GCPnts_AbscissaPoint::Length(curve) <= 1e-6 * m.diagonal) continue;
          // Tangent or coplanar faces along the whole edge: no crease of their own.
          bool transversal = false;
          for (int k = 0; k < 5 && !transversal; ++k) {
            const double u = curve.FirstParameter() + (k + 0.5) / 5 * (curve.LastParameter() - curve.FirstParameter());
            const gp_Pnt p = curve.Value(u);
            gp_Vec na, nb;
            if (!outwardNormalAt(solidA->face(j.faceA), p, na) || !outwardNormalAt(solidB->face(j.faceB), p, nb)) continue;
            transversal = na.Crossed(nb).Magnitude() > tangentSine;
          }
          if (!transversal) continue;
          classify(oracle, j, creaseAngle, control);
          if (!j.kept.empty()) m.junctions.push_back(std::move(j));
        }
      }
    }
  } catch (const Standard_Failure& failure) {
    throw Error(std::string("OpenCASCADE failed while computing the junction curves between inputs (") +
                failure.GetMessageString() + "): check the solids with Part > Check geometry");
  }
  return result;
}

FeatureGraph JunctionCurves::polylines(double maxSegmentLength, double sagittaTolerance) const {
  if (!(maxSegmentLength > 0) || !std::isfinite(maxSegmentLength))
    throw InputError("the feature edge size must be a positive number (edge_size), got " +
                     std::to_string(maxSegmentLength));
  if (!(sagittaTolerance > 0)) sagittaTolerance = featureSagittaTolerance(maxSegmentLength, impl_->diagonal);
  FeatureGraph graph;
  try {
    for (size_t index = 0; index < impl_->junctions.size(); ++index) {
      const Junction& j = impl_->junctions[index];
      BRepAdaptor_Curve curve(j.edge);
      const double first = curve.FirstParameter(), last = curve.LastParameter();
      std::vector<std::pair<double, double>> kept = j.kept;
      // A closed curve kept through its vertex: one piece running through it.
      bool wrap = j.closed && kept.size() >= 2 && kept.front().first == first && kept.back().second == last;
      auto pointAt = [&](double t) {
        if (t == first) return j.firstPoint;
        if (t == last) return j.lastPoint;
        return toPoint3(curve.Value(t));
      };
      auto emit = [&](const std::vector<std::pair<double, double>>& parts, int minSegments) {
        FeaturePolyline pl;
        for (const auto& [a, b] : parts) {
          const std::vector<double> params = polylineParameters(curve, a, b, maxSegmentLength, sagittaTolerance, minSegments);
          for (size_t i = pl.points.empty() ? 0 : 1; i < params.size(); ++i) pl.points.push_back(pointAt(params[i]));
        }
        pl.junction = static_cast<int>(index);
        pl.curve = static_cast<int>(graph.polylines.size());
        graph.polylines.push_back(std::move(pl));
      };
      if (wrap) {
        emit({kept.back(), kept.front()}, 1);
        kept.pop_back();
        kept.erase(kept.begin());
      }
      for (const auto& part : kept) {
        const bool whole = j.closed && part.first == first && part.second == last;
        emit({part}, whole ? 3 : 1);
      }
    }
  } catch (const Standard_Failure& failure) {
    throw Error(std::string("OpenCASCADE failed while sampling the junction curves (") + failure.GetMessageString() +
                ")");
  }
  return graph;
}

BoundaryProjection JunctionCurves::projectOnCurve(int junction, const Point3& p) const {
  BoundaryProjection result;
  if (junction < 0 || junction >= static_cast<int>(impl_->junctions.size())) return result;
  const Junction& j = impl_->junctions[junction];
  try {
    BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(toGp(p)).Vertex(), j.edge, Extrema_ExtFlag_MIN);
    if (!dist.IsDone() || dist.NbSolution() == 0) return result;
    result.point = toPoint3(dist.PointOnShape2(1));
    result.distance = dist.Value();
    result.patch = j.faceA;
  } catch (const Standard_Failure& failure) {
    throw Error(std::string("OpenCASCADE failed to project a point onto a junction curve (") +
                failure.GetMessageString() + ")");
  }
  return result;
}

// ------------------------------------------------------------------------------------------

namespace {

// Closest points of segments p1-q1 and p2-q2 (Ericson, Real-Time Collision Detection 5.1.9).
double closestSegmentPoints(const Point3& p1, const Point3& q1, const Point3& p2, const Point3& q2, double& s,
                            double& t) {
  const Point3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  if (a <= 0 && e <= 0) {
    s = t = 0;
    return distance(p1, p2);
  }
  if (a <= 0) {
    s = 0;
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = dot(d1, r);
    if (e <= 0) {
      t = 0;
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = dot(d1, d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return distance(p1 + s * d1, p2 + t * d2);
}

double longestSegment(const FeaturePolyline& pl) {
  double l = 0;
  for (size_t i = 0; i + 1 < pl.points.size(); ++i) l = std::max(l, distance(pl.points[i], pl.points[i + 1]));
  return l;
}

Bbox boxOf(const FeaturePolyline& pl) {
  Bbox b;
  for (const Point3& p : pl.points) b.add(p);
  return b;
}

// The point `offset` along the polyline (backwards when negative) from `from`, clamped at the
// polyline's ends.
Point3 walkAlong(const std::vector<Point3>& pts, const PolylineFoot& from, double offset) {
  size_t segment = from.segment;
  double along = from.along * distance(pts[segment], pts[segment + 1]) + offset;  // from pts[segment]
  while (along < 0 && segment > 0) along += distance(pts[segment - 1], pts[segment]), --segment;
  while (segment + 2 < pts.size() && along > distance(pts[segment], pts[segment + 1]))
    along -= distance(pts[segment], pts[segment + 1]), ++segment;
  const double length = distance(pts[segment], pts[segment + 1]);
  const double t = length > 0 ? std::clamp(along / length, 0.0, 1.0) : 0.0;
  return pts[segment] + t * (pts[segment + 1] - pts[segment]);
}

}  // namespace

FeatureGraph joinJunctions(const FeatureGraph& sharp, const FeatureGraph& junctionPolylines,
                           const HierarchicalOracle& oracle, const JunctionCurves& junctions) {
  std::vector<FeaturePolyline> all = sharp.polylines;
  const size_t sharpCount = all.size();
  all.insert(all.end(), junctionPolylines.polylines.begin(), junctionPolylines.polylines.end());
  const double diagonal = oracle.diagonal();
  const double weld = 1e-6 * diagonal;  // features closer than this meet

  auto project = [&](const FeaturePolyline& pl, const Point3& p) -> Point3 {
    if (pl.junction >= 0) {
      const BoundaryProjection q = junctions.projectOnCurve(pl.junction, p);
      if (std::isfinite(q.distance)) return q.point;
    } else if (pl.source >= 0 && pl.edge >= 0 && pl.source < static_cast<int>(oracle.entries().size())) {
      if (const auto* solid = oracle.entries()[pl.source].source->brepTopology()) {
        const BoundaryProjection q = solid->projectOnEdge(p, pl.edge);
        if (std::isfinite(q.distance)) return q.point;
      }
    }
    return nearestOnPolyline(pl.points, p).point;
  };

  std::vector<double> reach(all.size());
  std::vector<Bbox> boxes(all.size());
  for (size_t i = 0; i < all.size(); ++i) {
    reach[i] = 0.1 * longestSegment(all[i]) + weld;  // chord-to-curve allowance
    boxes[i] = boxOf(all[i]);
  }

  // Contacts between a junction polyline and any other polyline, on both exact curves.
  struct Contact {
    Point3 point;
    size_t a, b;
  };
  std::vector<Contact> contacts;
  try {
    for (size_t j = sharpCount; j < all.size(); ++j) {
      for (size_t k = 0; k < all.size(); ++k) {
        if (k == j || (k >= sharpCount && k < j)) continue;  // each junction pair once
        const double r = reach[j] + reach[k];
        bool near = true;
        for (int c = 0; c < 3; ++c)
          near = near && boxes[j].min[c] <= boxes[k].max[c] + r && boxes[k].min[c] <= boxes[j].max[c] + r;
        if (!near) continue;
        const auto& pj = all[j].points;
        const auto& pk = all[k].points;
        for (size_t sj = 0; sj + 1 < pj.size(); ++sj)
          for (size_t sk = 0; sk + 1 < pk.size(); ++sk) {
            double s, t;
            const double d = closestSegmentPoints(pj[sj], pj[sj + 1], pk[sk], pk[sk + 1], s, t);
            if (d > r) continue;
            Point3 x = 0.5 * ((pj[sj] + s * (pj[sj + 1] - pj[sj])) + (pk[sk] + t * (pk[sk + 1] - pk[sk])));
            Point3 onJ = x, onK = x;
            for (int it = 0; it < 60; ++it) {
              onJ = project(all[j], x);
              onK = project(all[k], onJ);
              if (distance(onJ, onK) <= 1e-13 * diagonal) break;
              x = onK;
            }
            if (distance(onJ, onK) > weld) continue;
            const Point3 c = k < sharpCount ? onK : onJ;  // a B-rep edge is the exact one
            // The exact curves may meet beyond the (clipped) polylines.
            const PolylineFoot footJ = nearestOnPolyline(pj, c);
            if (footJ.distance > reach[j] || nearestOnPolyline(pk, c).distance > reach[k]) continue;
            // Where the two curves run along each other (a junction along a sharp edge: the
            // presse's circle where a rod leaves a nut's face at the rim of a bore), the chords
            // come close everywhere and every such contact would cut both curves at an
            // arbitrary point; removeCoincidentFeatures drops the junction there instead. A
            // contact is kept where the curves cross, touch or part: not on both curves a
            // quarter segment away on either side.
            const double step = 0.25 * distance(pj[footJ.segment], pj[footJ.segment + 1]);
            auto onBoth = [&](const Point3& q) {
              const Point3 qj = project(all[j], q);
              return distance(qj, project(all[k], qj)) <= weld && nearestOnPolyline(pk, qj).distance <= reach[k];
            };
            if (step > weld && onBoth(walkAlong(pj, footJ, -step)) && onBoth(walkAlong(pj, footJ, step))) continue;
            contacts.push_back({c, j, k});
          }
      }
    }
  } catch (const Standard_Failure& failure) {
    throw Error(std::string("OpenCASCADE failed while joining junction curves to the feature edges (") +
                failure.GetMessageString() + ")");
  }

  // Contacts within `weld` of each other are one point: an existing sharp-edge end (exact
  // B-rep vertex or clip point) when there is one, else an existing junction end.
  std::vector<int> cluster(contacts.size(), -1);
  std::vector<Point3> canonical;
  for (size_t i = 0; i < contacts.size(); ++i) {
    for (size_t c = 0; c < canonical.size() && cluster[i] < 0; ++c)
      if (distance(contacts[i].point, canonical[c]) <= 2 * weld) cluster[i] = static_cast<int>(c);
    if (cluster[i] >= 0) continue;
    Point3 best = contacts[i].point;
    bool found = false;
    for (size_t p = 0; p < all.size() && !found; ++p)
      for (const Point3& end : {all[p].points.front(), all[p].points.back()})
        if (distance(end, contacts[i].point) <= weld) {
          best = end;
          found = true;
          break;
        }
    cluster[i] = static_cast<int>(canonical.size());
    canonical.push_back(best);
  }

  // Per polyline, the shared points on it; then split there.
  std::vector<std::vector<int>> splitsOf(all.size());
  for (size_t i = 0; i < contacts.size(); ++i)
    for (size_t p : {contacts[i].a, contacts[i].b}) splitsOf[p].push_back(cluster[i]);
  std::map<Point3, Point3> movedEnds;  // old end -> shared point, applied to every polyline
  std::vector<FeaturePolyline> out;
  for (size_t p = 0; p < all.size(); ++p) {
    std::vector<Point3> pts = all[p].points;
    std::vector<char> split(pts.size(), 0);
    std::vector<int>& mine = splitsOf[p];
    std::sort(mine.begin(), mine.end());
    mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
    const bool closed = pts.size() > 2 && pts.front() == pts.back();
    for (int c : mine) {
      const Point3& q = canonical[c];
      size_t nearest = 0;
      for (size_t v = 1; v < pts.size(); ++v)
        if (distance(pts[v], q) < distance(pts[nearest], q)) nearest = v;
      if (distance(pts[nearest], q) <= 2 * weld) {
        const bool end = nearest == 0 || nearest + 1 == pts.size();
        if (end && !(pts[nearest] == q)) movedEnds[pts[nearest]] = q;
        if (closed && end) {
          pts.front() = pts.back() = q;
          split.front() = split.back() = 1;
        } else {
          pts[nearest] = q;
          split[nearest] = 1;
        }
        continue;
      }
      const size_t s = nearestOnPolyline(pts, q).segment;
      pts.insert(pts.begin() + s + 1, q);
      split.insert(split.begin() + s + 1, 1);
    }
    // A closed polyline split inside: start it at its first split point.
    if (closed && !split.front()) {
      size_t first = 0;
      while (first < split.size() && !split[first]) ++first;
      if (first < split.size()) {
        std::vector<Point3> rotated(pts.begin() + first, pts.end() - 1);
        rotated.insert(rotated.end(), pts.begin(), pts.begin() + first + 1);
        std::vector<char> flags(split.begin() + first, split.end() - 1);
        flags.insert(flags.end(), split.begin(), split.begin() + first + 1);
        pts = std::move(rotated);
        split = std::move(flags);
      }
    }
    FeaturePolyline piece = all[p];
    piece.points.clear();
    for (size_t v = 0; v < pts.size(); ++v) {
      piece.points.push_back(pts[v]);
      if (split[v] && v > 0 && v + 1 < pts.size()) {
        out.push_back(piece);
        piece.points.assign(1, pts[v]);
      }
    }
    out.push_back(std::move(piece));
  }

  FeatureGraph joined;
  for (FeaturePolyline& pl : out) {
    for (Point3* end : {&pl.points.front(), &pl.points.back()}) {
      auto it = movedEnds.find(*end);
      if (it != movedEnds.end()) *end = it->second;
    }
    double length = 0;
    for (size_t i = 0; i + 1 < pl.points.size(); ++i) length += distance(pl.points[i], pl.points[i + 1]);
    if (pl.points.size() < 2 || length <= weld) continue;
    pl.curve = static_cast<int>(joined.polylines.size());
    joined.polylines.push_back(std::move(pl));
  }
  return joined;
}

}  // namespace oraclemesh
