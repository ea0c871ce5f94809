#include "domain/HierarchicalOracle.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Error.h"
#include "domain/CoordinateRange.h"

namespace oraclemesh {

HierarchicalOracle::HierarchicalOracle(std::vector<OracleEntry> entries) : entries_(std::move(entries)) {
  if (entries_.empty())
    throw InputError("the job has no inputs: add at least one solid with role 'material'");
  bool anyMaterial = false;
  for (const OracleEntry& e : entries_) {
    if (!e.source) throw InputError("an input has no geometry: give it a file, BREP text or a sphere");
    // Every kind of input, before either engine sees points that rounding has merged.
    requireCoordinateRange(e.source->bbox(), "input '" + e.source->name() + "'");
    if (e.role == Role::Material) {
      if (e.material <= 0)
        throw InputError("input '" + e.source->name() + "' has material id " + std::to_string(e.material) +
                         ": material ids must be positive integers (1, 2, ...)");
      anyMaterial = true;
      bbox_.add(e.source->bbox());
    }
  }
  if (!anyMaterial)
    throw InputError("all inputs have role 'cut', so nothing is left to mesh: give at least one input role 'material'");
}

int HierarchicalOracle::decidingEntry(const Point3& p) const {
  if (!bbox_.contains(p)) return -1;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Source& s = *entries_[i].source;
    // The bbox test is the cheap reject that keeps most queries away from the exact test.
    if (s.bbox().contains(p) && s.inside(p)) return static_cast<int>(i);
  }
  return -1;
}

int HierarchicalOracle::label(const Point3& p) const {
  const int i = decidingEntry(p);
  if (i < 0 || entries_[i].role == Role::Cut) return 0;
  return entries_[i].material;
}

double HierarchicalOracle::distanceToMaterial(const Point3& p, int material, double reach) const {
  double nearest = std::numeric_limits<double>::infinity();
  for (const OracleEntry& e : entries_) {
    if (e.role != Role::Material || e.material != material || !e.source->bbox().contains(p, reach)) continue;
    if (e.source->inside(p)) return 0;
    nearest = std::min(nearest, e.source->project(p).distance);
  }
  return nearest;
}

bool HierarchicalOracle::coveredByHigherEntry(const Point3& p, int entry) const {
  const double tol = 1e3 * tolerance();  // "strictly inside": farther than this from the boundary
  for (int i = 0; i < entry && i < static_cast<int>(entries_.size()); ++i) {
    const Source& s = *entries_[i].source;
    if (!s.bbox().contains(p) || !s.inside(p)) continue;
    if (s.project(p).distance > tol) return true;
  }
  return false;
}

namespace {

// Whether the segment a + t d, t in [0, 1], meets the box grown by `margin`.
bool segmentMeetsBox(const Point3& a, const Point3& d, const Bbox& box, double margin) {
  if (box.empty()) return false;
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double lo = box.min[i] - margin, hi = box.max[i] + margin;
    if (d[i] == 0.0) {
      if (a[i] < lo || a[i] > hi) return false;
      continue;
    }
    double ta = (lo - a[i]) / d[i], tb = (hi - a[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace

std::vector<CompositeCrossing> HierarchicalOracle::crossings(const Point3& a, const Point3& b) const {
  // A segment from infinity has no crossings anyone could place; its points would reach the
  // inputs' exact queries as NaN.
  if (!isFinite(a) || !isFinite(b))
    throw Error("internal error: a crossing query along a segment with an end that is not a finite point");
  std::vector<CompositeCrossing> result;
  const Point3 d = b - a;
  const double length = norm(d);
  if (length == 0.0) return result;

  struct Event {
    BoundaryCrossing crossing;
    int entry;
  };
  std::vector<Event> events;
  // Each entry's state at t = 0: outside if its first crossing enters, and for an entry the
  // segment does not cross, its state anywhere on the segment (taken at the midpoint, away
  // from an endpoint that may lie on its boundary).
  std::vector<char> inside(entries_.size(), 0);
  const Point3 middle = a + 0.5 * d;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Source& source = *entries_[i].source;
    if (!segmentMeetsBox(a, d, source.bbox(), tolerance())) continue;
    const std::vector<BoundaryCrossing> own = source.crossings(a, b);
    if (own.empty()) {
      inside[i] = source.inside(middle);
      continue;
    }
    inside[i] = !own.front().entering;
    for (const BoundaryCrossing& c : own) events.push_back({c, static_cast<int>(i)});
  }
  std::stable_sort(events.begin(), events.end(),
                   [](const Event& x, const Event& y) { return x.crossing.t < y.crossing.t; });

  auto decider = [&]() {
    for (size_t i = 0; i < entries_.size(); ++i)
      if (inside[i]) return static_cast<int>(i);
    return -1;
  };
  auto labelOf = [&](int entry) {
    return entry < 0 || entries_[entry].role == Role::Cut ? 0 : entries_[entry].material;
  };
  const double sameT = tolerance() / length;
  for (size_t first = 0; first < events.size();) {
    size_t last = first;
    while (last + 1 < events.size() && events[last + 1].crossing.t - events[first].crossing.t <= sameT) ++last;
    const int deciderBefore = decider();
    for (size_t k = first; k <= last; ++k) inside[events[k].entry] = events[k].crossing.entering;
    const int deciderAfter = decider();
    const int before = labelOf(deciderBefore), after = labelOf(deciderAfter);
    if (before != after) {
      // The boundary crossed here belongs to the entry deciding one of the two sides.
      const Event* chosen = &events[first];
      for (size_t k = first; k <= last; ++k)
        if (events[k].entry == deciderBefore || events[k].entry == deciderAfter) {
          if (chosen->entry != deciderBefore && chosen->entry != deciderAfter) chosen = &events[k];
          else if (events[k].entry < chosen->entry) chosen = &events[k];
        }
      CompositeCrossing crossing;
      crossing.t = chosen->crossing.t;
      crossing.point = chosen->crossing.point;
      crossing.entry = chosen->entry;
      crossing.patch = chosen->crossing.patch;
      crossing.labelBefore = before;
      crossing.labelAfter = after;
      result.push_back(crossing);
    }
    first = last + 1;
  }
  return result;
}

BoundaryProjection HierarchicalOracle::projectOnBoundary(const Point3& p, int* entry) const {
  // Exact projections are costly (OpenCASCADE extrema): visit the entries nearest by
  // bounding box first and stop once a box is farther than the best boundary point found.
  auto boxDistance = [&](const Bbox& box) {
    double squared = 0;
    for (int i = 0; i < 3; ++i) {
      const double outside = std::max({box.min[i] - p[i], 0.0, p[i] - box.max[i]});
      squared += outside * outside;
    }
    return std::sqrt(squared);
  };
  std::vector<std::pair<double, size_t>> order;
  for (size_t i = 0; i < entries_.size(); ++i) order.push_back({boxDistance(entries_[i].source->bbox()), i});
  std::sort(order.begin(), order.end());
  BoundaryProjection best;
  int bestEntry = -1;
  // A point this close to a boundary is on it (the thesis engine puts its surface vertices
  // on the boundary up to rounding): the entries farther in the order could only win by a
  // distance that moves nothing, and projecting onto them (OpenCASCADE for B-reps) was most
  // of the boundary snap's time for such meshes.
  const double onBoundary = 1e-3 * tolerance();
  for (const auto& [lowerBound, i] : order) {
    if (lowerBound > best.distance || best.distance <= onBoundary) break;
    const BoundaryProjection q = entries_[i].source->project(p);
    if (q.distance < best.distance || (q.distance == best.distance && static_cast<int>(i) < bestEntry)) {
      best = q;
      bestEntry = static_cast<int>(i);
    }
  }
  if (entry) *entry = bestEntry;
  return best;
}

}  // namespace oraclemesh
