// A face's domain by its parametric triangles: how far the domain may reach past each
// boundary chord (measured once), and whether a point's parameters lie in the domain.
#include "domain/brep/BrepSolidImpl.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <map>

namespace oraclemesh {

void BrepSolid::Impl::measureChordReach() {
  std::vector<std::vector<size_t>> trianglesOfFace(faces.size());
  for (size_t id = 0; id < proxyFaceOfTriangle.size(); ++id) trianglesOfFace[proxyFaceOfTriangle[id]].push_back(id);
  period.assign(faces.size(), {0.0, 0.0});
  for (size_t f = 0; f < faces.size(); ++f) {
    const BRepAdaptor_Surface surface(faces[f], Standard_True);
    if (surface.IsUPeriodic()) period[f][0] = surface.UPeriod();
    if (surface.IsVPeriodic()) period[f][1] = surface.VPeriod();
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull() || !tri->HasUVNodes()) continue;
    // Parametric sagitta of each chord of each edge: the edge's parametric curve at the middle
    // parameter against the chord's middle; plus the edge's tolerance in parameter units.
    std::map<std::pair<int, int>, double> reachOfChord;
    for (TopExp_Explorer ex(faces[f], TopAbs_EDGE); ex.More(); ex.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(ex.Current());
      TopLoc_Location edgeLoc;
      const Handle(Poly_PolygonOnTriangulation) polygon = BRep_Tool::PolygonOnTriangulation(edge, tri, edgeLoc);
      if (polygon.IsNull() || polygon->Parameters().IsNull()) continue;
      double first, last;
      const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, faces[f], first, last);
      if (pcurve.IsNull()) continue;
      const double tolerance = 2 * BRep_Tool::Tolerance(edge) + classifyTolerance;
      const TColStd_Array1OfInteger& nodes = polygon->Nodes();
      const TColStd_Array1OfReal& parameters = polygon->Parameters()->Array1();
      for (int i = nodes.Lower(); i < nodes.Upper(); ++i) {
        const gp_Pnt2d p0 = tri->UVNode(nodes(i)), p1 = tri->UVNode(nodes(i + 1));
        const gp_Pnt2d middle((p0.XY() + p1.XY()) / 2);
        const gp_Pnt2d onCurve = pcurve->Value(0.5 * (parameters(i) + parameters(i + 1)));
        // A 3D tolerance in parameters: divided by the smaller speed of the parametrisation.
        gp_Pnt point;
        gp_Vec du, dv;
        surface.D1(middle.X(), middle.Y(), point, du, dv);
        const double speed = std::min(du.Magnitude(), dv.Magnitude());
        if (!(speed > 1e-9)) continue;  // degenerate here: leave the chord unmeasured
        // A seam's polygon and parametric curve may be those of its two sides: compare
        // them modulo the periods.
        gp_XY gap = onCurve.XY() - middle.XY();
        if (period[f][0] > 0) gap.SetX(gap.X() - period[f][0] * std::round(gap.X() / period[f][0]));
        if (period[f][1] > 0) gap.SetY(gap.Y() - period[f][1] * std::round(gap.Y() / period[f][1]));
        const double reach = 1.5 * gap.Modulus() + tolerance / speed;
        double& slot = reachOfChord[{std::min(nodes(i), nodes(i + 1)), std::max(nodes(i), nodes(i + 1))}];
        slot = std::max(slot, reach);
      }
    }
    for (size_t id : trianglesOfFace[f]) {
      NewtonTriangle& triangle = newtonTriangle[id];
      for (int k = 0; k < 3; ++k) {
        if (!triangle.boundaryEdge[k]) continue;
        const int p = triangle.corner[k], q = triangle.corner[(k + 1) % 3];
        const auto it = reachOfChord.find({std::min(p, q), std::max(p, q)});
        if (it != reachOfChord.end()) triangle.chordReach[k] = it->second;
      }
    }
  }
}

BrepSolid::Impl::Domain BrepSolid::Impl::domainByTriangles(const gp_Pnt& p, int face, double& u, double& v,
                                                           const size_t* triangles, size_t count) const {
  const double uPeriod = period[face][0], vPeriod = period[face][1];
  const double band = crossingBand[face];
  bool inside = false;
  double insideU = u, insideV = v;
  for (size_t i = 0; i < count; ++i) {
    const NewtonTriangle& triangle = newtonTriangle[triangles[i]];
    const gp_XY p0 = triangle.uv[0].XY(), e1 = triangle.uv[1].XY() - p0, e2 = triangle.uv[2].XY() - p0;
    // (u, v) in the period of this triangle's parameters.
    double uu = u, vv = v;
    if (uPeriod > 0) uu += uPeriod * std::round((p0.X() + (e1.X() + e2.X()) / 3 - u) / uPeriod);
    if (vPeriod > 0) vv += vPeriod * std::round((p0.Y() + (e1.Y() + e2.Y()) / 3 - v) / vPeriod);
    const gp_XY q(uu, vv);
    for (int k = 0; k < 3; ++k) {
      if (!triangle.boundaryEdge[k]) continue;
      if (triangle.chordReach[k] < 0) {
        const gp_XYZ s0 = triangle.node[k].XYZ(), chord = triangle.node[(k + 1) % 3].XYZ() - s0;
        const double lengthSquared = chord.SquareModulus();
        const double along = lengthSquared > 0 ? std::clamp((p.XYZ() - s0).Dot(chord) / lengthSquared, 0.0, 1.0) : 0.0;
        if ((p.XYZ() - (s0 + along * chord)).SquareModulus() <= band * band) return Domain::Unsure;
        continue;
      }
      const gp_XY s0 = triangle.uv[k].XY(), chord = triangle.uv[(k + 1) % 3].XY() - s0;
      const double lengthSquared = chord.SquareModulus();
      const double along = lengthSquared > 0 ? std::clamp((q - s0).Dot(chord) / lengthSquared, 0.0, 1.0) : 0.0;
      if ((q - (s0 + along * chord)).SquareModulus() <= triangle.chordReach[k] * triangle.chordReach[k])
        return Domain::Unsure;
    }
    if (inside) continue;
    const double area = e1.Crossed(e2);
    if (area == 0) continue;
    const gp_XY r = q - p0;
    const double w1 = r.Crossed(e2) / area, w2 = e1.Crossed(r) / area;
    const double slack = -1e-9;  // a point on an edge shared by two triangles is in either
    if (w1 >= slack && w2 >= slack && 1 - w1 - w2 >= slack) {
      inside = true;
      insideU = uu;
      insideV = vv;
    }
  }
  if (!inside) return Domain::Out;
  u = insideU;
  v = insideV;
  return Domain::In;
}

}  // namespace oraclemesh
