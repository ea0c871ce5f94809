#include "domain/Source.h"

namespace oraclemesh {

std::vector<BoundaryCrossing> crossingsByBisection(const Source& source, const Point3& a,
                                                  const Point3& b, int samples, double tolerance) {
  std::vector<BoundaryCrossing> result;
  const double length = distance(a, b);
  if (length == 0.0) return result;
  auto at = [&](double t) { return a + t * (b - a); };
  bool previousInside = source.inside(a);
  double previousT = 0.0;
  for (int i = 1; i <= samples; ++i) {
    const double t = double(i) / samples;
    const bool in = source.inside(at(t));
    if (in != previousInside) {
      double lo = previousT, hi = t;  // inside(lo) == previousInside, inside(hi) == in
      while ((hi - lo) * length > tolerance) {
        const double mid = 0.5 * (lo + hi);
        (source.inside(at(mid)) == previousInside ? lo : hi) = mid;
      }
      BoundaryCrossing crossing;
      crossing.t = 0.5 * (lo + hi);
      crossing.point = at(crossing.t);
      crossing.patch = source.project(crossing.point).patch;
      crossing.entering = in;
      result.push_back(crossing);
    }
    previousInside = in;
    previousT = t;
  }
  return result;
}

std::vector<BoundaryCrossing> Source::crossings(const Point3& a, const Point3& b) const {
  const double tolerance = 1e-9 * std::max(bbox().diagonal(), distance(a, b));
  return crossingsByBisection(*this, a, b, 64, tolerance);
}

}  // namespace oraclemesh
