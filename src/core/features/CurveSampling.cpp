#include "features/CurveSampling.h"

#include <GCPnts_AbscissaPoint.hxx>
#include <GCPnts_UniformAbscissa.hxx>
#include <gp_Vec.hxx>

#include <algorithm>
#include <cmath>

namespace oraclemesh {

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
    for (size_t i = 0; i + 1 < params.size(); ++i) {
      const gp_Pnt a = curve.Value(params[i]), b = curve.Value(params[i + 1]);
      const gp_Pnt mid = curve.Value(0.5 * (params[i] + params[i + 1]));
      const gp_Vec chord(a, b);
      const double chordLength = chord.Magnitude();
      const double sagitta =
          chordLength > 0 ? gp_Vec(a, mid).Crossed(chord).Magnitude() / chordLength : a.Distance(mid);
      worstSagitta = std::max(worstSagitta, sagitta);
    }
    if (worstSagitta <= sagittaTolerance) break;
    segments *= 2;
  }
  return params;
}

}  // namespace oraclemesh
