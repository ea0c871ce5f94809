#include "features/UserPolylines.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "Error.h"
#include "domain/BrepSolid.h"

// OpenCASCADE after the project headers (its Handle macro breaks CGAL's).
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>

namespace oraclemesh {

namespace {

std::string where(size_t polyline, const Point3& p) {
  std::ostringstream out;
  out << "features.polylines[" << polyline << "] leaves the meshed domain near (" << p[0] << ", " << p[1] << ", "
      << p[2] << "): draw it inside or on the parts (not in a cut region or outside every input)";
  return out.str();
}

// Parameters (s on segment a->b, t on c->d) of the closest points of two segments.
void closestParameters(const Point3& a, const Point3& b, const Point3& c, const Point3& d, double& s, double& t) {
  const Point3 u = b - a, v = d - c, w = a - c;
  const double uu = dot(u, u), uv = dot(u, v), vv = dot(v, v), uw = dot(u, w), vw = dot(v, w);
  const double denominator = uu * vv - uv * uv;
  s = denominator > 1e-14 * uu * vv ? std::clamp((uv * vw - vv * uw) / denominator, 0.0, 1.0) : 0.0;
  t = vv > 0 ? std::clamp((uv * s + vw) / vv, 0.0, 1.0) : 0.0;
  // With t clamped, s must be recomputed for the true closest pair.
  s = uu > 0 ? std::clamp((uv * t - uw) / uu, 0.0, 1.0) : 0.0;
}

// Whether a segment of one polyline lies on the other (both ends and its middle within
// `tolerance`).
bool shareAStretch(const FeaturePolyline& x, const FeaturePolyline& y, double tolerance) {
  auto on = [&](const FeaturePolyline& pl, const Point3& p) {
    return distance(nearestOnPolyline(pl.points, p), p) <= tolerance;
  };
  for (const auto& [from, to] : {std::pair{&x, &y}, std::pair{&y, &x}})
    for (size_t k = 0; k + 1 < from->points.size(); ++k)
      if (on(*to, from->points[k]) && on(*to, from->points[k + 1]) &&
          on(*to, 0.5 * (from->points[k] + from->points[k + 1])))
        return true;
  return false;
}

constexpr double kSinMinCrossingAngle = 0.0174524;  // sin(1 degree)

bool boxesOverlap(const Bbox& a, const Bbox& b, double margin) {
  for (int k = 0; k < 3; ++k)
    if (a.min[k] > b.max[k] + margin || b.min[k] > a.max[k] + margin) return false;
  return true;
}

}  // namespace

FeatureGraph userPolylineFeatures(const std::vector<std::vector<Point3>>& polylines, const HierarchicalOracle& oracle,
                                  double maxSegmentLength,
                                  const std::vector<std::shared_ptr<const UserCurve>>& curves) {
  FeatureGraph graph;
  const double onBoundary = 1e-6 * oracle.diagonal();
  for (size_t i = 0; i < polylines.size(); ++i) {
    const std::vector<Point3>& in = polylines[i];
    const UserCurve* exact = i < curves.size() ? curves[i].get() : nullptr;
    // Each given segment is a polyline of its own: Mesh_3 keeps polyline ends as vertices but
    // may cut across a kink in the middle of a polyline.
    for (size_t k = 0; k + 1 < in.size(); ++k) {
      FeaturePolyline out;
      out.user = static_cast<int>(i);
      const int pieces = std::max(1, static_cast<int>(std::ceil(distance(in[k], in[k + 1]) / maxSegmentLength)));
      for (int j = 0; j <= pieces; ++j)
        out.points.push_back(j == pieces ? in[k + 1] : in[k] + (double(j) / pieces) * (in[k + 1] - in[k]));
      // Every vertex and segment middle inside the composite domain or on its boundary.
      for (size_t m = 0; m < out.points.size(); ++m) {
        std::vector<Point3> probes{out.points[m]};
        if (m + 1 < out.points.size()) probes.push_back(0.5 * (out.points[m] + out.points[m + 1]));
        for (const Point3& probe : probes) {
          const Point3 p = exact ? exact->nearest(probe) : probe;
          if (oracle.label(p) == 0 && oracle.projectOnBoundary(p).distance > onBoundary) throw InputError(where(i, p));
        }
      }
      graph.polylines.push_back(std::move(out));
    }
  }
  return graph;
}

FeatureGraph splitAtCrossings(const FeatureGraph& graph, double tolerance, double curveTolerance,
                              double sharedEndClearance) {
  // Split parameters per polyline: segment index -> points to insert on it.
  std::vector<std::map<size_t, std::vector<Point3>>> inserts(graph.polylines.size());
  std::vector<Bbox> boxes(graph.polylines.size());
  for (size_t i = 0; i < graph.polylines.size(); ++i)
    for (const Point3& p : graph.polylines[i].points) boxes[i].add(p);
  // A CAD curve's end this close to a meeting point is where it meets the other curve.
  const double endClearance = 100 * curveTolerance;
  auto nearestEnd = [](const FeaturePolyline& pl, const Point3& p) {
    return distance(pl.points.front(), p) <= distance(pl.points.back(), p) ? pl.points.front() : pl.points.back();
  };
  // The end both polylines share near p, if any.
  auto nearSharedEnd = [&](const FeaturePolyline& x, const FeaturePolyline& y, const Point3& p) {
    for (const Point3& e : {x.points.front(), x.points.back()})
      if (distance(e, p) <= sharedEndClearance &&
          (distance(e, y.points.front()) <= curveTolerance || distance(e, y.points.back()) <= curveTolerance))
        return true;
    return false;
  };
  for (size_t i = 0; i < graph.polylines.size(); ++i) {
    const FeaturePolyline& first = graph.polylines[i];
    for (size_t j = i + 1; j < graph.polylines.size(); ++j) {
      const FeaturePolyline& second = graph.polylines[j];
      const bool userPair = first.user >= 0 || second.user >= 0;
      const double reach = userPair ? tolerance : curveTolerance;
      if (!userPair && curveTolerance <= 0) continue;
      if (!boxesOverlap(boxes[i], boxes[j], reach)) continue;
      int overlapping = -1;  // whether the two CAD curves share a stretch; found when needed
      for (size_t a = 0; a + 1 < first.points.size(); ++a)
        for (size_t b = 0; b + 1 < second.points.size(); ++b) {
          double s, t;
          closestParameters(first.points[a], first.points[a + 1], second.points[b], second.points[b + 1], s, t);
          const Point3 onFirst = first.points[a] + s * (first.points[a + 1] - first.points[a]);
          const Point3 onSecond = second.points[b] + t * (second.points[b + 1] - second.points[b]);
          if (distance(onFirst, onSecond) > reach) continue;
          if (userPair) {
            // The crossing point is taken on the CAD curve (it lies on the CAD edge).
            const Point3 meeting = first.user < 0    ? onFirst
                                   : second.user < 0 ? onSecond
                                                     : 0.5 * (onFirst + onSecond);
            inserts[i][a].push_back(meeting);
            inserts[j][b].push_back(meeting);
            continue;
          }
          // Curves meeting at less than a degree are tangent there, not crossing (chords of
          // two tangent curves come within the tolerance over a length).
          const Point3 u = first.points[a + 1] - first.points[a], v = second.points[b + 1] - second.points[b];
          if (norm(cross(u, v)) < kSinMinCrossingAngle * norm(u) * norm(v)) continue;
          // Curves leaving a common end (a B-rep vertex, a clip point) at a small angle stay
          // close for a while: that is their meeting at the end, not a crossing.
          if (nearSharedEnd(first, second, onFirst)) continue;
          // Edges of two parts in contact can run along one another (the same arc on both):
          // they meet at every shared sample, and none of it is a crossing.
          if (overlapping == -1) overlapping = shareAStretch(first, second, curveTolerance) ? 1 : 0;
          if (overlapping == 1) continue;
          const Point3 endOfFirst = nearestEnd(first, onFirst), endOfSecond = nearestEnd(second, onSecond);
          const bool atEndOfFirst = distance(endOfFirst, onFirst) <= endClearance;
          const bool atEndOfSecond = distance(endOfSecond, onSecond) <= endClearance;
          if (atEndOfFirst && atEndOfSecond) continue;
          if (atEndOfFirst) {  // a T: the first curve ends on the second one
            inserts[j][b].push_back(endOfFirst);
          } else if (atEndOfSecond) {
            inserts[i][a].push_back(endOfSecond);
          } else {
            const Point3 meeting = 0.5 * (onFirst + onSecond);
            inserts[i][a].push_back(meeting);
            inserts[j][b].push_back(meeting);
          }
        }
    }
  }
  FeatureGraph result;
  for (size_t i = 0; i < graph.polylines.size(); ++i) {
    const FeaturePolyline& pl = graph.polylines[i];
    // Rebuild the point list with the meeting points, remembering which points are cuts.
    std::vector<Point3> points;
    std::vector<char> cut;
    auto add = [&](const Point3& p, bool isCut, double snap) {
      if (!points.empty() && distance(points.back(), p) <= snap) {
        if (isCut) {  // a meeting point replaces the vertex it falls on, so both curves share it
          points.back() = p;
          cut.back() = 1;
        }
        return;
      }
      points.push_back(p);
      cut.push_back(isCut);
    };
    for (size_t k = 0; k < pl.points.size(); ++k) {
      add(pl.points[k], false, tolerance);
      auto it = inserts[i].find(k);
      if (it == inserts[i].end() || k + 1 == pl.points.size()) continue;
      std::vector<Point3> along = it->second;
      const Point3 start = pl.points[k];
      std::sort(along.begin(), along.end(),
                [&](const Point3& x, const Point3& y) { return distance(start, x) < distance(start, y); });
      for (const Point3& p : along) add(p, true, tolerance);
    }
    // Break the polyline at every meeting point: pieces meet only at their ends.
    FeaturePolyline piece = pl;
    piece.points.clear();
    for (size_t k = 0; k < points.size(); ++k) {
      piece.points.push_back(points[k]);
      const bool end = k + 1 == points.size();
      if ((cut[k] && k > 0 && !end) || end) {
        if (piece.points.size() >= 2) {
          piece.curve = static_cast<int>(result.polylines.size());
          result.polylines.push_back(piece);
        }
        piece.points = {points[k]};
      }
    }
  }
  return result;
}

Point3 nearestOnPolyline(const std::vector<Point3>& polyline, const Point3& p) {
  Point3 best = polyline.front();
  for (size_t k = 0; k + 1 < polyline.size(); ++k) {
    const Point3 u = polyline[k + 1] - polyline[k];
    const double uu = dot(u, u);
    const double t = uu > 0 ? std::clamp(dot(p - polyline[k], u) / uu, 0.0, 1.0) : 0.0;
    const Point3 q = polyline[k] + t * u;
    if (distance(p, q) < distance(p, best)) best = q;
  }
  return best;
}

struct UserCurve::Data {
  TopoDS_Edge edge;
  std::string where;
};

UserCurve::UserCurve(std::unique_ptr<Data> data) : data_(std::move(data)) {}
UserCurve::~UserCurve() = default;

std::shared_ptr<const UserCurve> UserCurve::fromBrep(const std::string& text, const std::string& where) {
  const std::string fix = ": give BREP text of one edge (Part.Edge.exportBrepToString()) or leave 'brep' out";
  const TopoDS_Shape shape = readBrepText(text, where, fix);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(shape, TopAbs_EDGE, edges);
  if (edges.Extent() != 1) throw InputError(where + " holds " + std::to_string(edges.Extent()) + " edges" + fix);
  const TopoDS_Edge edge = TopoDS::Edge(edges(1));
  if (BRep_Tool::Degenerated(edge)) throw InputError(where + " is a degenerate edge (a point)" + fix);
  auto data = std::make_unique<Data>();
  data->edge = edge;
  data->where = where;
  return std::shared_ptr<const UserCurve>(new UserCurve(std::move(data)));
}

Point3 UserCurve::nearest(const Point3& p) const {
  try {
    // A fresh query per point: OpenCASCADE's curve adaptors cache evaluations, so sharing one
    // between threads would not be safe.
    BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(gp_Pnt(p[0], p[1], p[2])).Vertex(), data_->edge,
                                    Extrema_ExtFlag_MIN);
    if (dist.IsDone() && dist.NbSolution() > 0) {
      const gp_Pnt q = dist.PointOnShape2(1);
      return {q.X(), q.Y(), q.Z()};
    }
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to project a point onto the edge of " + data_->where + " (" +
                failure.GetMessageString() + ")");
  }
  throw Error("OpenCASCADE found no point of the edge of " + data_->where + " near (" + std::to_string(p[0]) + ", " +
              std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")");
}

}  // namespace oraclemesh
