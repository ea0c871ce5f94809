#include "features/RuleSetQ.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <tuple>

#include "features/UserPolylines.h"

namespace oraclemesh {

namespace {

// Polyline ends are exact B-rep vertices or clip points computed once and copied, so equal
// ends agree to rounding; a grid of cell size `tolerance` finds them without an O(n^2) scan.
using GridCell = std::array<long long, 3>;

GridCell cellOf(const Point3& p, double tolerance) {
  return {static_cast<long long>(std::floor(p[0] / tolerance)), static_cast<long long>(std::floor(p[1] / tolerance)),
          static_cast<long long>(std::floor(p[2] / tolerance))};
}

double endSegmentLength(const FeaturePolyline& polyline, bool atStart) {
  const std::vector<Point3>& p = polyline.points;
  return atStart ? distance(p[0], p[1]) : distance(p[p.size() - 1], p[p.size() - 2]);
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
    return nearestOnPolyline(pl.points, p).distance <= tolerance;
  };
  for (const auto& [from, to] : {std::pair{&x, &y}, std::pair{&y, &x}})
    for (size_t k = 0; k + 1 < from->points.size(); ++k)
      if (on(*to, from->points[k]) && on(*to, from->points[k + 1]) &&
          on(*to, 0.5 * (from->points[k] + from->points[k + 1])))
        return true;
  return false;
}

// The index of pl's segment nearest to p.
size_t nearestSegment(const std::vector<Point3>& pl, const Point3& p) {
  size_t best = 0;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k + 1 < pl.size(); ++k) {
    const double d = distanceToSegment(p, pl[k], pl[k + 1]);
    if (d < bestDistance) {
      bestDistance = d;
      best = k;
    }
  }
  return best;
}

// Where curve `x` (near its segment `a`) touches curve `y` tangentially: the point of x's exact
// curve nearest to y's, searched (golden section) over x's chords from the sample before
// segment a to the one after it, each chord point taken onto x's exact curve. The distance
// to y has one minimum there (it grows with the square of the distance from the touching
// point). Nullopt when a projection is unknown.
std::optional<Point3> touchingPoint(const FeaturePolyline& x, size_t a, const FeaturePolyline& y,
                                    const ExactCurveProjection& project) {
  const size_t from = a > 0 ? a - 1 : a, to = std::min(a + 2, x.points.size() - 1);
  std::vector<double> along{0};  // chord length at each sample from `from`
  for (size_t k = from; k < to; ++k) along.push_back(along.back() + distance(x.points[k], x.points[k + 1]));
  auto onX = [&](double s) -> std::optional<Point3> {
    size_t k = 0;
    while (k + 2 < along.size() && s > along[k + 1]) ++k;
    const double length = along[k + 1] - along[k];
    const double t = length > 0 ? std::clamp((s - along[k]) / length, 0.0, 1.0) : 0.0;
    return project(x, x.points[from + k] + t * (x.points[from + k + 1] - x.points[from + k]));
  };
  auto gapAt = [&](double s) {
    const std::optional<Point3> p = onX(s);
    const std::optional<Point3> q = p ? project(y, *p) : std::nullopt;
    return q ? distance(*p, *q) : std::numeric_limits<double>::infinity();
  };
  constexpr double kGolden = 0.6180339887498949;
  double lo = 0, hi = along.back();
  double s1 = hi - kGolden * (hi - lo), s2 = lo + kGolden * (hi - lo);
  double g1 = gapAt(s1), g2 = gapAt(s2);
  for (int iteration = 0; iteration < 60 && hi - lo > 1e-12 * along.back(); ++iteration) {
    if (g1 <= g2) {
      hi = s2;
      s2 = s1;
      g2 = g1;
      s1 = hi - kGolden * (hi - lo);
      g1 = gapAt(s1);
    } else {
      lo = s1;
      s1 = s2;
      g1 = g2;
      s2 = lo + kGolden * (hi - lo);
      g2 = gapAt(s2);
    }
  }
  if (!std::isfinite(std::min(g1, g2))) return std::nullopt;
  return onX(g1 <= g2 ? s1 : s2);
}

constexpr double kSinMinCrossingAngle = 0.0174524;  // sin(1 degree)
constexpr double kSinNearTangent = 0.1736482;  // sin(10 degrees)
// Exact curves closer than this fraction of the pair tolerance touch.
constexpr double kTouchingGapPerTolerance = 1e-3;
// A sample where the polyline turns by less than this (cos 20 degrees) may move to a crossing.
constexpr double kCosStraightEnough = 0.9397;

bool boxesOverlap(const Bbox& a, const Bbox& b, double margin) {
  for (int k = 0; k < 3; ++k)
    if (a.min[k] > b.max[k] + margin || b.min[k] > a.max[k] + margin) return false;
  return true;
}

}  // namespace

FeatureGraph splitAtCrossings(const FeatureGraph& graph, double tolerance, double curveTolerance,
                              double sharedEndClearance, const ExactCurveGap& exactCurveGap,
                              const ExactCurveProjection& exactCurveProjection) {
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
      // Crossings of this pair, taken after all segment pairs are seen: next to a sample, the
      // chord beyond it also passes within reach of the other curve, and that near miss is
      // the same crossing, not a second one.
      struct Crossing {
        size_t a, b;
        Point3 point;
        double gap;
      };
      std::vector<Crossing> crossings;
      std::vector<Crossing> tangents;  // chord pairs within reach, nearly parallel (below)
      int overlapping = -1;  // whether the two CAD curves share a stretch; found when needed
      int exactCurvesApart = -1;  // whether the exact curves never come within `tolerance`; likewise
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
          // Chords meeting at less than a degree are of curves tangent there, not crossing
          // (chords of two tangent curves come within the tolerance over a length); where the
          // exact curves are known, so are chords meeting at under ten degrees (a circle resting
          // on a line: its chords cross the line at a few degrees a chord's length away from
          // where the curves touch). The exact curves decide them, after this loop.
          const Point3 u = first.points[a + 1] - first.points[a], v = second.points[b + 1] - second.points[b];
          const double sine = norm(cross(u, v)) / (norm(u) * norm(v));
          if (sine < kSinMinCrossingAngle || (sine < kSinNearTangent && exactCurveProjection)) {
            tangents.push_back({a, b, 0.5 * (onFirst + onSecond), distance(onFirst, onSecond)});
            continue;
          }
          // Curves leaving a common end (a B-rep vertex, a clip point) at a small angle stay
          // close for a while: that is their meeting at the end, not a crossing.
          if (nearSharedEnd(first, second, onFirst)) continue;
          // Edges of two parts in contact can run along one another (the same arc on both):
          // they meet at every shared sample, and none of it is a crossing.
          if (overlapping == -1) overlapping = shareAStretch(first, second, curveTolerance) ? 1 : 0;
          if (overlapping == 1) continue;
          if (exactCurvesApart == -1) exactCurvesApart = exactCurveGap && exactCurveGap(first, second) > tolerance ? 1 : 0;
          if (exactCurvesApart == 1) continue;
          const Point3 endOfFirst = nearestEnd(first, onFirst), endOfSecond = nearestEnd(second, onSecond);
          const bool atEndOfFirst = distance(endOfFirst, onFirst) <= endClearance;
          const bool atEndOfSecond = distance(endOfSecond, onSecond) <= endClearance;
          // Both ends near the meeting point: the curves meet at their ends (an L), unless
          // neither end lies on the other curve: then they cross a short way from both ends
          // (an overhanging box's bottom edge across the top edge of the box it stands on).
          auto liesOn = [&](const Point3& end, const FeaturePolyline& other) {
            return nearestOnPolyline(other.points, end).distance <= curveTolerance;
          };
          const bool crossingNearBothEnds =
              atEndOfFirst && atEndOfSecond && !liesOn(endOfFirst, second) && !liesOn(endOfSecond, first);
          if (crossingNearBothEnds) {
            crossings.push_back({a, b, 0.5 * (onFirst + onSecond), distance(onFirst, onSecond)});
            continue;
          }
          if (atEndOfFirst && atEndOfSecond) continue;
          if (atEndOfFirst && liesOn(endOfFirst, second)) {  // a T: the first curve ends on the second one
            inserts[j][b].push_back(endOfFirst);
          } else if (atEndOfSecond && liesOn(endOfSecond, first)) {
            inserts[i][a].push_back(endOfSecond);
          } else {
            crossings.push_back({a, b, 0.5 * (onFirst + onSecond), distance(onFirst, onSecond)});
          }
        }
      if (!tangents.empty() && exactCurveGap && exactCurveProjection) {
        const double touching = kTouchingGapPerTolerance * tolerance;
        // Sample points lie on their own exact curve; on the other's too only where the two
        // curves coincide.
        auto onCurve = [&](const FeaturePolyline& curve, const Point3& p) {
          const std::optional<Point3> q = exactCurveProjection(curve, p);
          return q && distance(*q, p) <= touching;
        };
        double exactGap = -2;  // not asked yet
        std::stable_sort(tangents.begin(), tangents.end(), [](const Crossing& x, const Crossing& y) { return x.gap < y.gap; });
        std::vector<size_t> seen;  // first's segments whose neighbourhood is decided
        for (const Crossing& closest : tangents) {
          if (std::any_of(seen.begin(), seen.end(), [&](size_t a) { return std::max(a, closest.a) - std::min(a, closest.a) <= 2; }))
            continue;
          seen.push_back(closest.a);
          const double chord = distance(first.points[closest.a], first.points[closest.a + 1]);
          const bool sharedStretch =
              onCurve(second, first.points[closest.a]) && onCurve(second, first.points[closest.a + 1]) &&
              onCurve(first, second.points[closest.b]) && onCurve(first, second.points[closest.b + 1]);
          if (sharedStretch || nearSharedEnd(first, second, closest.point) ||
              std::any_of(crossings.begin(), crossings.end(),
                          [&](const Crossing& c) { return distance(c.point, closest.point) <= 2 * chord; }))
            continue;
          for (const auto& [x, y, onY] : {std::tuple{&first, &second, j}, std::tuple{&second, &first, i}}) {
            const Point3 end = nearestEnd(*x, closest.point);
            if (distance(end, closest.point) > endClearance || distance(nearestEnd(*y, end), end) <= curveTolerance ||
                !onCurve(*y, end))
              continue;
            inserts[onY][nearestSegment(y->points, end)].push_back(end);
          }
          if (exactGap == -2) exactGap = exactCurveGap(first, second);
          if (!(exactGap >= 0 && exactGap <= touching)) continue;
          const std::optional<Point3> point = touchingPoint(first, closest.a, second, exactCurveProjection);
          if (!point) continue;
          const std::optional<Point3> onOther = exactCurveProjection(second, *point);
          auto awayFromEnds = [&](const FeaturePolyline& pl) { return distance(nearestEnd(pl, *point), *point) > touching; };
          if (onOther && distance(*onOther, *point) <= touching && distance(*point, closest.point) <= 2 * chord &&
              awayFromEnds(first) && awayFromEnds(second))
            crossings.push_back({nearestSegment(first.points, *point), nearestSegment(second.points, *point), *point, 0});
        }
      }
      // The closest approach stands for the near misses within reach of it.
      std::stable_sort(crossings.begin(), crossings.end(),
                       [](const Crossing& x, const Crossing& y) { return x.gap < y.gap; });
      std::vector<Point3> taken;
      for (const Crossing& c : crossings) {
        if (std::any_of(taken.begin(), taken.end(), [&](const Point3& p) { return distance(p, c.point) <= reach; }))
          continue;
        taken.push_back(c.point);
        inserts[i][c.a].push_back(c.point);
        inserts[j][c.b].push_back(c.point);
      }
    }
  }
  FeatureGraph result;
  for (size_t i = 0; i < graph.polylines.size(); ++i) {
    const FeaturePolyline& pl = graph.polylines[i];
    // Rebuild the point list with the meeting points, remembering which points are cuts.
    std::vector<Point3> points;
    std::vector<char> cut;
    // A vertex within the snap distance of the point before is dropped (a curve sampled finer
    // than that, by sizes from the geometry, is thinned to it), but never the curve's last one:
    // other curves share it as their end.
    auto add = [&](const Point3& p, bool isCut, bool isEnd, double snap) {
      if (!points.empty() && distance(points.back(), p) <= snap) {
        if (isCut) {  // a meeting point replaces the vertex it falls on, so both curves share it
          points.back() = p;
          cut.back() = 1;
          return;
        }
        if (!isEnd || cut.back()) return;  // a meeting point just before stands for the end
        if (points.size() > 1) {
          points.back() = p;
          return;
        }
      }
      points.push_back(p);
      cut.push_back(isCut);
    };
    // A meeting point close to an inner sample of its segment (under kCrossingSpread of the
    // segment) takes that sample's place instead of joining it: a short piece next to a
    // crossing would force elements far smaller than the sizes around it (graded sampling puts
    // samples anywhere along a curve). The curve's ends stay: other curves share them; so does
    // a sample where the polyline turns (a corner of a joined curve).
    constexpr double kCrossingSpread = 1.0 / 3;
    std::vector<Point3> samples = pl.points;
    std::vector<char> moved(samples.size(), 0);
    auto movable = [&](size_t k) {
      if (k == 0 || k + 1 >= pl.points.size() || moved[k]) return false;
      const Point3 u = pl.points[k] - pl.points[k - 1], v = pl.points[k + 1] - pl.points[k];
      return dot(u, v) > kCosStraightEnough * norm(u) * norm(v);
    };
    for (auto& [k, along] : inserts[i]) {
      if (k + 1 >= pl.points.size()) continue;
      const double length = distance(pl.points[k], pl.points[k + 1]);
      for (auto p = along.begin(); p != along.end();) {
        size_t target = pl.points.size();
        if (movable(k) && distance(pl.points[k], *p) < kCrossingSpread * length)
          target = k;
        else if (movable(k + 1) && distance(*p, pl.points[k + 1]) < kCrossingSpread * length)
          target = k + 1;
        if (target == pl.points.size()) {
          ++p;
          continue;
        }
        samples[target] = *p;
        moved[target] = 1;
        p = along.erase(p);
      }
    }
    for (size_t k = 0; k < pl.points.size(); ++k) {
      add(samples[k], moved[k] != 0, k + 1 == pl.points.size(), tolerance);
      auto it = inserts[i].find(k);
      if (it == inserts[i].end() || k + 1 == pl.points.size()) continue;
      std::vector<Point3> along = it->second;
      const Point3 start = pl.points[k];
      std::sort(along.begin(), along.end(),
                [&](const Point3& x, const Point3& y) { return distance(start, x) < distance(start, y); });
      for (const Point3& p : along) add(p, true, false, tolerance);
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

std::vector<StarVertex> findStarVertices(const FeatureGraph& graph, double tolerance) {
  std::vector<StarVertex> vertices;
  std::map<GridCell, std::vector<int>> grid;  // cell -> indices into `vertices`
  auto vertexAt = [&](const Point3& p) -> StarVertex& {
    const GridCell c = cellOf(p, tolerance);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (int v : it->second)
            if (distance(vertices[v].point, p) <= tolerance) return vertices[v];
        }
    grid[c].push_back(static_cast<int>(vertices.size()));
    vertices.push_back(StarVertex{p, {}, 0});
    return vertices.back();
  };
  for (size_t i = 0; i < graph.polylines.size(); ++i) {
    const FeaturePolyline& pl = graph.polylines[i];
    if (pl.points.size() < 2) continue;
    vertexAt(pl.points.front()).incident.push_back({static_cast<int>(i), true});
    vertexAt(pl.points.back()).incident.push_back({static_cast<int>(i), false});
  }
  std::vector<StarVertex> stars;
  for (StarVertex& v : vertices) {
    if (v.incident.size() < 2) continue;
    v.shortest_incident_length = std::numeric_limits<double>::infinity();
    for (const StarVertex::Incident& e : v.incident)
      v.shortest_incident_length =
          std::min(v.shortest_incident_length, endSegmentLength(graph.polylines[e.polyline], e.at_start));
    stars.push_back(std::move(v));
  }
  std::sort(stars.begin(), stars.end(), [](const StarVertex& a, const StarVertex& b) { return a.point < b.point; });
  return stars;
}

FeatureGraph equalizeStarSegments(const FeatureGraph& graph, const std::vector<StarVertex>& stars) {
  // Where each polyline end is a star vertex: the distance from the end to its new point.
  std::vector<double> startCut(graph.polylines.size(), 0), endCut(graph.polylines.size(), 0);
  std::map<Point3, int> starAt;  // star vertices by their (bitwise) end points
  for (size_t k = 0; k < stars.size(); ++k)
    for (const StarVertex::Incident& e : stars[k].incident) {
      const FeaturePolyline& pl = graph.polylines[e.polyline];
      starAt[e.at_start ? pl.points.front() : pl.points.back()] = static_cast<int>(k);
    }
  for (const StarVertex& star : stars) {
    // Free (thesis fig. 3.3): equal incident lengths and no incident segment reaching another
    // star vertex. Lengths compare to rounding, as a previous equalisation leaves them.
    bool free = true;
    for (const StarVertex::Incident& e : star.incident) {
      const FeaturePolyline& pl = graph.polylines[e.polyline];
      const Point3& neighbour = e.at_start ? pl.points[1] : pl.points[pl.points.size() - 2];
      free = free && endSegmentLength(pl, e.at_start) <= star.shortest_incident_length * (1 + 1e-9) &&
             !starAt.count(neighbour);
    }
    if (free || !(star.shortest_incident_length > 0)) continue;
    for (const StarVertex::Incident& e : star.incident)
      (e.at_start ? startCut : endCut)[e.polyline] = star.shortest_incident_length / 3;
  }
  FeatureGraph result = graph;
  for (size_t i = 0; i < graph.polylines.size(); ++i) {
    std::vector<Point3>& p = result.polylines[i].points;
    if (p.size() < 2 || (startCut[i] == 0 && endCut[i] == 0)) continue;
    // Both cuts are taken on the original end segments; on a one-segment polyline they are at
    // most a third of it from each end, so they stay in order.
    const Point3 first = p[0], second = p[1], last = p[p.size() - 1], beforeLast = p[p.size() - 2];
    if (endCut[i] > 0) {
      const Point3 back = last + (endCut[i] / distance(last, beforeLast)) * (beforeLast - last);
      p.insert(p.end() - 1, back);
    }
    if (startCut[i] > 0) {
      const Point3 front = first + (startCut[i] / distance(first, second)) * (second - first);
      p.insert(p.begin() + 1, front);
    }
  }
  return result;
}

}  // namespace oraclemesh
