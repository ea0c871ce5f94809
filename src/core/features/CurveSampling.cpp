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
