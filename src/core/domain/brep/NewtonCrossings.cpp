// Crossings by Newton iteration on the exact surface, from a proxy triangle the segment
// crosses or passes steeply.
#include "domain/brep/BrepSolidImpl.h"

namespace oraclemesh {

BrepSolid::Impl::NewtonResult BrepSolid::Impl::newtonCrossing(const Point3& a, const Point3& d, double length,
                                                              int face, const NewtonSeed& seed, double& t,
                                                              gp_Pnt2d& uv) const {
  const NewtonTriangle& triangle = newtonTriangle[seed.triangle];
  const std::array<double, 3>& w = seed.weight;
  double u = w[0] * triangle.uv[0].X() + w[1] * triangle.uv[1].X() + w[2] * triangle.uv[2].X();
  double v = w[0] * triangle.uv[0].Y() + w[1] * triangle.uv[1].Y() + w[2] * triangle.uv[2].Y();
  t = seed.t;
  const gp_XYZ dir(d[0], d[1], d[2]);
  // Far below the 1e-7 x diagonal agreement with OpenCASCADE, above double round-off.
  const double tolerance = 1e-12 * diagonal;
  bool converged = false;
  for (int iteration = 0; iteration < 8 && !converged; ++iteration) {
    gp_Pnt p;
    gp_Vec su, sv;
    faceSurface[face]->D1(u, v, p, su, sv);
    // F = S(u,v) - (a + t d); J = [Su Sv -d]; solve J delta = -F by Cramer's rule.
    const gp_XYZ residual(p.X() - (a[0] + t * d[0]), p.Y() - (a[1] + t * d[1]), p.Z() - (a[2] + t * d[2]));
    if (residual.Modulus() <= tolerance) {
      converged = true;
      break;
    }
    const gp_XYZ cu = su.XYZ(), cv = sv.XYZ(), cd = dir.Reversed();
    const double det = cu.Dot(cv.Crossed(cd));
    // Near-singular: a pole, a degenerate parametrisation or a grazing line.
    if (!(std::abs(det) > 0.05 * cu.Modulus() * cv.Modulus() * length)) return NewtonResult::Unsure;
    const gp_XYZ rhs = residual.Reversed();
    u += rhs.Dot(cv.Crossed(cd)) / det;
    v += cu.Dot(rhs.Crossed(cd)) / det;
    t += cu.Dot(cv.Crossed(rhs)) / det;
    if (!std::isfinite(u) || !std::isfinite(v) || !std::isfinite(t)) return NewtonResult::Unsure;
  }
  if (!converged) return NewtonResult::Unsure;
  // Near an end of the segment OpenCASCADE's own rounding decides whether the crossing
  // counts: leave that to it, as any crossing within the face's band of an end.
  const double endMargin = crossingBand[face] / length;
  if (std::abs(t) <= endMargin || std::abs(1 - t) <= endMargin) return NewtonResult::Unsure;
  // The solution must lie on the seed's own parametric triangle: elsewhere it may be the
  // crossing over a neighbour triangle, and this triangle's own crossing not found.
  const gp_XY p0 = triangle.uv[0].XY(), e1 = triangle.uv[1].XY() - p0, e2 = triangle.uv[2].XY() - p0;
  const gp_XY q = gp_XY(u, v) - p0;
  const double area = e1.Crossed(e2);
  if (area == 0) return NewtonResult::Unsure;
  const double w1 = q.Crossed(e2) / area, w2 = e1.Crossed(q) / area;
  const double slack = -1e-9;
  uv.SetCoord(u, v);
  if (!(w1 >= slack && w2 >= slack && 1 - w1 - w2 >= slack)) return NewtonResult::OffTriangle;
  if (t < 0 || t > 1) return NewtonResult::None;
  return NewtonResult::Crossing;
}

}  // namespace oraclemesh
