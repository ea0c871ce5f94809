#include "features/TangentCusps.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <utility>

namespace oraclemesh {
namespace {

double polylineLength(const std::vector<Point3>& points) {
  double length = 0;
  for (size_t k = 0; k + 1 < points.size(); ++k) length += distance(points[k], points[k + 1]);
  return length;
}

// The polyline's points as seen from one end: index k from that end.
struct EndView {
  const std::vector<Point3>* points;
  bool atBack;
  size_t size() const { return points->size(); }
  const Point3& operator[](size_t k) const { return atBack ? (*points)[points->size() - 1 - k] : (*points)[k]; }
  size_t original(size_t k) const { return atBack ? points->size() - 1 - k : k; }
};

struct Trim {
  size_t trimmed = 0;
  bool atBack = false;
  size_t lost = 0;         // samples of the trimmed polyline replaced from that end (the end included)
  size_t kept = 0;
  size_t keptSample = 0;   // index in the kept polyline's points
  TangentCusp cusp;
};

enum class Parting { NotTried, Parted, AtOnce, Never };

// The trim of polyline t at its end (front, or back when tBack) against polyline k sharing that
// end `vertex` (TangentCusps.h); nullopt where t parts from k at its first sample or never, or
// where the trim would reach the samples its other end lost (otherLost).
std::optional<Trim> trimAgainst(const FeatureGraph& graph, const Point3& vertex, size_t t, bool tBack, size_t k,
                                bool kBack, size_t otherLost, const std::function<double(const Point3&)>& edgeSize,
                                double widthPerEdgeSize, Parting& parting) {
  const EndView trimmed{&graph.polylines[t].points, tBack};
  const EndView kept{&graph.polylines[k].points, kBack};
  // The first sample of the trimmed curve that is far enough from the kept one.
  size_t parted = 1;
  double width = 0;
  for (; parted < trimmed.size(); ++parted) {
    width = nearestOnPolyline(*kept.points, trimmed[parted]).distance;
    if (width >= widthPerEdgeSize * edgeSize(trimmed[parted])) break;
  }
  parting = parted == 1 ? Parting::AtOnce : parted == trimmed.size() ? Parting::Never : Parting::Parted;
  if (parting != Parting::Parted) return std::nullopt;
  if (parted + otherLost > trimmed.size() - 1) return std::nullopt;
  // The kept curve's last sample before the parting: nearest to the last lost sample, and
  // nearer the vertex than the first sample kept, so the new first segment runs on.
  const double reach = distance(vertex, trimmed[parted - 1]) + 0.5 * distance(trimmed[parted - 1], trimmed[parted]);
  size_t q = 0;
  for (size_t s = 1; s < kept.size() && distance(vertex, kept[s]) < reach; ++s) q = s;
  if (q == 0) return std::nullopt;
  Trim trim;
  trim.trimmed = t;
  trim.atBack = tBack;
  trim.lost = parted;
  trim.kept = k;
  trim.keptSample = kept.original(q);
  trim.cusp.vertex = vertex;
  trim.cusp.trimmed_curve = graph.polylines[t].curve;
  trim.cusp.kept_curve = graph.polylines[k].curve;
  trim.cusp.source = graph.polylines[t].source;
  trim.cusp.trimmed_edge = graph.polylines[t].edge;
  trim.cusp.kept_edge = graph.polylines[k].edge;
  trim.cusp.parting_point = kept[q];
  trim.cusp.resumes_at = trimmed[parted];
  for (size_t s = 0; s + 1 < parted; ++s) trim.cusp.merged_length += distance(trimmed[s], trimmed[s + 1]);
  trim.cusp.width = width;
  return trim;
}

}  // namespace

FeatureGraph mergeTangentCusps(const FeatureGraph& graph, const LeavingDirection& leaving,
                               const std::function<double(const Point3&)>& edgeSize, double tangentAngleDeg,
                               double widthPerEdgeSize, std::vector<TangentCusp>* cusps) {
  const size_t n = graph.polylines.size();
  std::map<Point3, std::vector<std::pair<size_t, bool>>> ends;  // vertex -> (polyline, at its back)
  for (size_t i = 0; i < n; ++i) {
    const auto& points = graph.polylines[i].points;
    if (points.size() < 2) continue;
    ends[points.front()].push_back({i, false});
    ends[points.back()].push_back({i, true});
  }
  std::vector<double> lengths(n);
  for (size_t i = 0; i < n; ++i) lengths[i] = polylineLength(graph.polylines[i].points);

  std::vector<Trim> trims;
  std::vector<size_t> lostAt(2 * n, 0);  // per polyline end (2 i + atBack): samples it lost
  std::vector<char> keeps(n, 0), trimmedAny(n, 0);
  const double sinLimit = std::sin(tangentAngleDeg * M_PI / 180);
  for (const auto& [vertex, list] : ends) {
    if (list.size() < 2) continue;
    std::vector<Point3> directions;  // each end's, once (exact tangents: OpenCASCADE projections)
    for (const auto& [i, atBack] : list) directions.push_back(leaving(graph.polylines[i], atBack));
    for (size_t x = 0; x < list.size(); ++x)
      for (size_t y = x + 1; y < list.size(); ++y) {
        auto [a, aBack] = list[x];
        auto [b, bBack] = list[y];
        if (a == b) continue;
        const Point3& ta = directions[x];
        const Point3& tb = directions[y];
        // Tangent and leaving the same way (a curve continuing the other one is not a cusp).
        if (dot(ta, tb) <= 0 || norm(cross(ta, tb)) >= sinLimit * norm(ta) * norm(tb)) continue;
        // The user's own polylines are kept whole: the other curve gives way, or neither.
        const bool aUser = graph.polylines[a].user >= 0, bUser = graph.polylines[b].user >= 0;
        if (aUser && bUser) continue;
        const bool aShorter = lengths[a] < lengths[b] ||
                              (lengths[a] == lengths[b] && graph.polylines[a].curve > graph.polylines[b].curve);
        const bool trimA = aUser ? false : bUser ? true : aShorter;
        const auto [t, tBack] = trimA ? std::pair{a, aBack} : std::pair{b, bBack};
        const auto [k, kBack] = trimA ? std::pair{b, bBack} : std::pair{a, aBack};
        std::optional<Trim> trim;
        Parting parting = Parting::NotTried;
        if (lostAt[2 * t + tBack] == 0 && !keeps[t] && !trimmedAny[k])
          trim = trimAgainst(graph, vertex, t, tBack, k, kBack, lostAt[2 * t + !tBack], edgeSize, widthPerEdgeSize, parting);
        // The shorter curve may stay within reach of the longer one all along (a piece of a
        // curve split near the vertex, shorter than the stretch where the two run together):
        // then the longer one gives way, unless the user drew it.
        if (!trim && parting == Parting::Never && graph.polylines[k].user < 0 && lostAt[2 * k + kBack] == 0 &&
            !keeps[k] && !trimmedAny[t])
          trim = trimAgainst(graph, vertex, k, kBack, t, tBack, lostAt[2 * k + !kBack], edgeSize, widthPerEdgeSize, parting);
        if (!trim) continue;
        lostAt[2 * trim->trimmed + trim->atBack] = trim->lost;
        trimmedAny[trim->trimmed] = 1;
        keeps[trim->kept] = 1;
        trims.push_back(*trim);
      }
  }

  FeatureGraph out;
  std::vector<std::set<size_t>> splits(n);  // inner samples where a kept polyline is split
  std::vector<std::array<const Trim*, 2>> trimsOf(n, {nullptr, nullptr});
  for (const Trim& trim : trims) {
    trimsOf[trim.trimmed][trim.atBack] = &trim;
    if (trim.keptSample > 0 && trim.keptSample + 1 < graph.polylines[trim.kept].points.size())
      splits[trim.kept].insert(trim.keptSample);
  }
  for (size_t i = 0; i < n; ++i) {
    const FeaturePolyline& pl = graph.polylines[i];
    if (trimmedAny[i]) {
      FeaturePolyline piece = pl;
      const Trim* front = trimsOf[i][0];
      const Trim* back = trimsOf[i][1];
      const size_t first = front ? front->lost : 0;
      const size_t last = back ? pl.points.size() - 1 - back->lost : pl.points.size() - 1;
      piece.points.clear();
      if (front) piece.points.push_back(front->cusp.parting_point);
      for (size_t s = first; s <= last; ++s) piece.points.push_back(pl.points[s]);
      if (back) piece.points.push_back(back->cusp.parting_point);
      out.polylines.push_back(std::move(piece));
      continue;
    }
    size_t from = 0;
    for (size_t at : splits[i]) {
      FeaturePolyline piece = pl;
      piece.points.assign(pl.points.begin() + from, pl.points.begin() + at + 1);
      out.polylines.push_back(std::move(piece));
      from = at;
    }
    FeaturePolyline piece = pl;
    piece.points.assign(pl.points.begin() + from, pl.points.end());
    out.polylines.push_back(std::move(piece));
  }
  for (size_t i = 0; i < out.polylines.size(); ++i) out.polylines[i].curve = static_cast<int>(i);
  if (cusps)
    for (const Trim& trim : trims) cusps->push_back(trim.cusp);
  return out;
}

}  // namespace oraclemesh
