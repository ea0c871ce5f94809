#include "features/CoincidentFeatures.h"

#include <algorithm>
#include <cmath>

#include "domain/BrepTopology.h"

namespace oraclemesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Whether points lie on the curve a polyline samples. The polyline's chords are within the
// sampling sagitta of that curve; a B-rep edge polyline is asked about its exact edge.
class SampledCurves {
 public:
  SampledCurves(const HierarchicalOracle& oracle, double tol, double curveTol)
      : oracle_(oracle), tol_(tol), curveTol_(curveTol) {}

  // `exact`: p is a sample of an exact curve (a polyline vertex), so on a shared curve it is on
  // the edge to rounding; otherwise p is a chord point, up to a sagitta off.
  bool onCurve(const Point3& p, const FeaturePolyline& pl, bool exact) const {
    const PolylineFoot foot = nearestOnPolyline(pl.points, p);
    const double chord = foot.distance;
    if (chord < tol_) return true;
    if (!(curveTol_ > 0) || chord >= curveTol_ + tol_) return false;
    // Beyond the polyline's ends its curve goes on (the rest of a B-rep edge, another piece of
    // it after a split) but the polyline does not: a point there is not along it.
    const bool closed = pl.points.size() > 2 && pl.points.front() == pl.points.back();
    const bool pastEnd = (foot.segment == 0 && foot.along <= 0) ||
                         (foot.segment + 2 == pl.points.size() && foot.along >= 1);
    if (!closed && pastEnd) return false;
    const BrepTopology* solid = solidOf(pl);
    if (!solid) return chord < curveTol_;
    return solid->projectOnEdge(p, pl.edge).distance < (exact ? tol_ : curveTol_);
  }

  // Whether vertex q of another polyline lies on pl's exact curve near segment [a, b].
  bool onExactCurveNear(const Point3& q, const FeaturePolyline& pl, const Point3& a, const Point3& b) const {
    const double chord = distanceToSegment(q, a, b);
    if (chord < tol_) return true;
    const BrepTopology* solid = solidOf(pl);
    return curveTol_ > 0 && solid && chord < curveTol_ && solid->projectOnEdge(q, pl.edge).distance < tol_;
  }

  double tolerance() const { return tol_; }

 private:
  const BrepTopology* solidOf(const FeaturePolyline& pl) const {
    if (pl.source < 0 || pl.edge < 0 || pl.source >= static_cast<int>(oracle_.entries().size())) return nullptr;
    return oracle_.entries()[pl.source].source->brepTopology();
  }

  const HierarchicalOracle& oracle_;
  double tol_, curveTol_;
};

// Inserts the vertices of `other` that lie on `pl`'s curve (strictly inside a segment) into `pl`.
void insertVerticesOf(FeaturePolyline& pl, const FeaturePolyline& other, const SampledCurves& curves) {
  const double tol = curves.tolerance();
  std::vector<Point3> out;
  for (size_t i = 0; i + 1 < pl.points.size(); ++i) {
    const Point3 a = pl.points[i], b = pl.points[i + 1];
    out.push_back(a);
    std::vector<std::pair<double, Point3>> inside;
    for (const Point3& q : other.points) {
      double t = 0;
      distanceToSegment(q, a, b, &t);
      if (t > 0 && t < 1 && distance(q, a) > tol && distance(q, b) > tol && curves.onExactCurveNear(q, pl, a, b))
        inside.emplace_back(t, q);
    }
    std::sort(inside.begin(), inside.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const auto& [t, q] : inside) out.push_back(q);
  }
  out.push_back(pl.points.back());
  pl.points = std::move(out);
}

// True when the composite boundary is flat across the segment at p: a ring of labels around
// the segment changes exactly twice, half a turn apart.
bool flatAcross(const HierarchicalOracle& oracle, const Point3& p, const Point3& tangent, double radius) {
  Point3 any = std::abs(tangent[0]) < 0.9 ? Point3{1, 0, 0} : Point3{0, 1, 0};
  Point3 e1 = cross(tangent, any);
  e1 = (1.0 / norm(e1)) * e1;
  const Point3 e2 = cross(tangent, e1);
  constexpr int kRing = 36;
  std::vector<int> labels(kRing);
  for (int k = 0; k < kRing; ++k) {
    const double angle = 2 * kPi * (k + 0.5) / kRing;
    labels[k] = oracle.label(p + radius * (std::cos(angle) * e1 + std::sin(angle) * e2));
  }
  std::vector<int> changes;
  for (int k = 0; k < kRing; ++k)
    if (labels[k] != labels[(k + 1) % kRing]) changes.push_back(k);
  if (changes.size() != 2) return changes.empty();
  const int apart = changes[1] - changes[0];
  return std::abs(apart - kRing / 2) <= 1;  // within 10 degrees of a straight angle
}

}  // namespace

FeatureGraph removeCoincidentFeatures(const FeatureGraph& graph, const HierarchicalOracle& oracle,
                                      double curveTolerance) {
  const double tol = 1e-7 * oracle.diagonal();
  const SampledCurves curves(oracle, tol, curveTolerance);
  const double ring = 1e-4 * oracle.diagonal();
  FeatureGraph result;
  std::vector<FeaturePolyline> kept;
  for (const FeaturePolyline& original : graph.polylines) {
    FeaturePolyline pl = original;
    for (const FeaturePolyline& earlier : kept) insertVerticesOf(pl, earlier, curves);
    const int entry = pl.source;
    // Split into runs of segments that are neither on an earlier polyline nor flat.
    std::vector<Point3> run;
    auto flush = [&]() {
      if (run.size() >= 2) {
        FeaturePolyline piece = pl;
        piece.points = run;
        kept.push_back(std::move(piece));
      }
      run.clear();
    };
    for (size_t i = 0; i + 1 < pl.points.size(); ++i) {
      const Point3 a = pl.points[i], b = pl.points[i + 1];
      const Point3 mid = 0.5 * (a + b);
      bool drop = std::any_of(kept.begin(), kept.end(), [&](const FeaturePolyline& e) {
        return curves.onCurve(a, e, true) && curves.onCurve(b, e, true) && curves.onCurve(mid, e, false);
      });
      if (!drop && entry > 0) {
        // On the boundary of a higher entry: keep only where the composite has a crease.
        for (int i2 = 0; i2 < entry && !drop; ++i2)
          if (oracle.entries()[i2].source->project(mid).distance < tol) {
            const double len = distance(a, b);
            drop = len > 0 && flatAcross(oracle, mid, (1.0 / len) * (b - a), ring);
          }
      }
      if (drop) {
        flush();
        continue;
      }
      if (run.empty()) run.push_back(a);
      run.push_back(b);
    }
    flush();
  }
  int curve = 0;
  for (FeaturePolyline& pl : kept) {
    pl.curve = curve++;
    result.polylines.push_back(std::move(pl));
  }
  return result;
}

}  // namespace oraclemesh
