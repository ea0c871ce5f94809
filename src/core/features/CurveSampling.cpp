#include "features/CurveSampling.h"

#include <BRepLProp_CLProps.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <GCPnts_UniformAbscissa.hxx>
#include <gp_Dir.hxx>

#include <algorithm>
#include <cmath>

namespace oraclemesh {

namespace {

// Distance of the curve point at the parametric middle of [u0, u1] from the chord.
double chordSagitta(const BRepAdaptor_Curve& curve, double u0, double u1) {
  const gp_Pnt a = curve.Value(u0), b = curve.Value(u1);
  const gp_Pnt mid = curve.Value(0.5 * (u0 + u1));
  const gp_Vec chord(a, b);
  const double chordLength = chord.Magnitude();
  return chordLength > 0 ? gp_Vec(a, mid).Crossed(chord).Magnitude() / chordLength : a.Distance(mid);
}

}  // namespace

std::vector<double> polylineParameters(const BRepAdaptor_Curve& curve, double first, double last,
                                       double maxSegmentLength, double sagittaTolerance, int minSegments) {
  const double length = GCPnts_AbscissaPoint::Length(curve, first, last);
  int segments = std::max(minSegments, static_cast<int>(std::ceil(length / maxSegmentLength)));
  std::vector<double> params;
  for (int attempt = 0; attempt < 12; ++attempt) {
    params.clear();
    GCPnts_UniformAbscissa uniform(curve, segments + 1, first, last);
    if (uniform.IsDone() && uniform.NbPoints() == segments + 1) {
      for (int i = 1; i <= uniform.NbPoints(); ++i) params.push_back(uniform.Parameter(i));
    } else {
      for (int i = 0; i <= segments; ++i) params.push_back(first + (last - first) * i / segments);
    }
    params.front() = first;
    params.back() = last;
    double worstSagitta = 0;
    for (size_t i = 0; i + 1 < params.size(); ++i)
      worstSagitta = std::max(worstSagitta, chordSagitta(curve, params[i], params[i + 1]));
    if (worstSagitta <= sagittaTolerance) break;
    segments *= 2;
  }
  return params;
}

std::vector<double> gradedPolylineParameters(const BRepAdaptor_Curve& curve, double first, double last,
                                             const std::function<double(const gp_Pnt&)>& localLength,
                                             double maxSegmentLength, double sagittaTolerance, int minSegments) {
  const double length = GCPnts_AbscissaPoint::Length(curve, first, last);
  auto lengthAt = [&](double u) { return std::min(maxSegmentLength, localLength(curve.Value(u))); };
  // March along the curve in steps of half the local length, recording arc length, parameter
  // and the integral of 1 / length (trapezoids). A local length that is not positive and
  // finite somewhere leaves the curve to the uniform split at maxSegmentLength.
  auto usable = [](double l) { return l > 0 && std::isfinite(l); };
  auto uniform = [&](double segmentLength) {
    return polylineParameters(curve, first, last, segmentLength, sagittaTolerance, minSegments);
  };
  struct Station {
    double arc, u, count;
  };
  std::vector<Station> stations{{0, first, 0}};
  double here = lengthAt(first);
  if (!usable(here)) return uniform(maxSegmentLength);
  double smallest = here, largest = here;
  while (stations.back().arc < length) {
    const Station previous = stations.back();
    const double step = std::min(0.5 * here, length - previous.arc);
    GCPnts_AbscissaPoint advance(curve, step, previous.u);
    const double u = advance.IsDone() ? std::min(advance.Parameter(), last) : last;
    const double next = lengthAt(u);
    if (!usable(next)) return uniform(maxSegmentLength);
    smallest = std::min(smallest, next);
    largest = std::max(largest, next);
    const double arc = (u >= last) ? length : previous.arc + step;
    stations.push_back({arc, u, previous.count + 0.5 * step * (1 / here + 1 / next)});
    here = next;
    if (u >= last) break;
  }
  stations.back().u = last;
  // A length that does not vary along the curve gives the uniform split exactly.
  if (smallest == largest) return uniform(smallest);
  const double total = stations.back().count;
  const int segments = std::max(minSegments, static_cast<int>(std::ceil(total - 1e-9)));
  std::vector<double> params{first};
  size_t k = 0;
  for (int i = 1; i < segments; ++i) {
    const double target = total * i / segments;
    while (k + 2 < stations.size() && stations[k + 1].count < target) ++k;
    const Station &a = stations[k], &b = stations[k + 1];
    const double t = b.count > a.count ? std::clamp((target - a.count) / (b.count - a.count), 0.0, 1.0) : 0.5;
    GCPnts_AbscissaPoint at(curve, t * (b.arc - a.arc), a.u);
    const double u = at.IsDone() ? at.Parameter() : a.u + t * (b.u - a.u);
    params.push_back(std::clamp(u, params.back(), last));
  }
  params.push_back(last);
  refineParameters(curve, params, [sagittaTolerance](const gp_Pnt&) { return sagittaTolerance; }, sagittaTolerance);
  return params;
}

void refineParameters(const BRepAdaptor_Curve& curve, std::vector<double>& params,
                      const std::function<double(const gp_Pnt&)>& localTolerance, double floorTolerance) {
  // Each pass halves the segments still too far off; a segment's sagitta shrinks about
  // fourfold per halving, so the floor is reached in a few dozen passes at most.
  constexpr int kMaxPasses = 40;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    std::vector<double> refined;
    refined.reserve(2 * params.size());
    bool split = false;
    for (size_t i = 0; i + 1 < params.size(); ++i) {
      refined.push_back(params[i]);
      const double middle = 0.5 * (params[i] + params[i + 1]);
      const double sagitta = chordSagitta(curve, params[i], params[i + 1]);
      if (sagitta > floorTolerance && sagitta > localTolerance(curve.Value(middle))) {
        refined.push_back(middle);
        split = true;
      }
    }
    refined.push_back(params.back());
    params.swap(refined);
    if (!split) break;
  }
}

bool unitTangent(const BRepAdaptor_Curve& curve, double u, gp_Vec& tangent) {
  BRepLProp_CLProps props(curve, u, 2, 1e-12);
  if (!props.IsTangentDefined()) return false;
  gp_Dir direction;
  props.Tangent(direction);
  tangent = gp_Vec(direction);
  return true;
}

}  // namespace oraclemesh
