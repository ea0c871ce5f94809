// Finite numbers everywhere in a shape's geometry, checked by reading the definitions
// (poles, axes, radii) rather than by evaluating them: evaluation is what must not see a NaN.
#include "domain/brep/FiniteGeometry.h"

#include <BRep_Tool.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_BezierCurve.hxx>
#include <Geom2d_Circle.hxx>
#include <Geom2d_Ellipse.hxx>
#include <Geom2d_Hyperbola.hxx>
#include <Geom2d_Line.hxx>
#include <Geom2d_OffsetCurve.hxx>
#include <Geom2d_Parabola.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_BezierCurve.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_Circle.hxx>
#include <Geom_ConicalSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Ellipse.hxx>
#include <Geom_Hyperbola.hxx>
#include <Geom_Line.hxx>
#include <Geom_OffsetCurve.hxx>
#include <Geom_OffsetSurface.hxx>
#include <Geom_Parabola.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <Geom_SurfaceOfLinearExtrusion.hxx>
#include <Geom_SurfaceOfRevolution.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>

#include <cmath>
#include <initializer_list>

#include "Error.h"

namespace oraclemesh {

namespace {

bool finite(std::initializer_list<double> values) {
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}
bool finite(const gp_XYZ& p) { return finite({p.X(), p.Y(), p.Z()}); }
bool finite(const gp_Pnt& p) { return finite(p.XYZ()); }
bool finite(const gp_Dir& d) { return finite(d.XYZ()); }
bool finite(const gp_Pnt2d& p) { return finite({p.X(), p.Y()}); }
bool finite(const gp_Dir2d& d) { return finite({d.X(), d.Y()}); }
bool finite(const gp_Ax3& a) {
  return finite(a.Location()) && finite(a.Direction()) && finite(a.XDirection()) && finite(a.YDirection());
}
bool finite(const gp_Ax2& a) { return finite(a.Location()) && finite(a.Direction()) && finite(a.XDirection()); }
bool finite(const gp_Ax22d& a) { return finite(a.Location()) && finite(a.XDirection()) && finite(a.YDirection()); }

bool finite(const TopLoc_Location& location) {
  const gp_Trsf t = location.Transformation();
  if (!finite(t.TranslationPart()) || !finite({t.ScaleFactor()})) return false;
  const gp_Mat m = t.VectorialPart();
  for (int i = 1; i <= 3; ++i)
    if (!finite({m.Value(i, 1), m.Value(i, 2), m.Value(i, 3)})) return false;
  return true;
}

template <class Spline>
bool finiteKnots(const Spline& s) {
  for (int i = 1; i <= s.NbKnots(); ++i)
    if (!finite({s.Knot(i)})) return false;
  return true;
}

template <class PolesOwner>
bool finitePolesAndWeights(const PolesOwner& c) {
  for (int i = 1; i <= c.NbPoles(); ++i)
    if (!finite(c.Pole(i)) || !finite({c.Weight(i)})) return false;
  return true;
}

bool finite(const Handle(Geom_Curve)& curve) {
  if (curve.IsNull()) return true;
  if (auto c = Handle(Geom_TrimmedCurve)::DownCast(curve))
    return finite({c->FirstParameter(), c->LastParameter()}) && finite(c->BasisCurve());
  if (auto c = Handle(Geom_OffsetCurve)::DownCast(curve))
    return finite({c->Offset()}) && finite(c->Direction()) && finite(c->BasisCurve());
  if (auto c = Handle(Geom_BSplineCurve)::DownCast(curve)) return finitePolesAndWeights(*c) && finiteKnots(*c);
  if (auto c = Handle(Geom_BezierCurve)::DownCast(curve)) return finitePolesAndWeights(*c);
  if (auto c = Handle(Geom_Line)::DownCast(curve))
    return finite(c->Position().Location()) && finite(c->Position().Direction());
  if (auto c = Handle(Geom_Conic)::DownCast(curve)) {
    if (!finite(c->Position())) return false;
    if (auto e = Handle(Geom_Circle)::DownCast(c)) return finite({e->Radius()});
    if (auto e = Handle(Geom_Ellipse)::DownCast(c)) return finite({e->MajorRadius(), e->MinorRadius()});
    if (auto e = Handle(Geom_Hyperbola)::DownCast(c)) return finite({e->MajorRadius(), e->MinorRadius()});
    if (auto e = Handle(Geom_Parabola)::DownCast(c)) return finite({e->Focal()});
  }
  return true;
}

bool finite(const Handle(Geom2d_Curve)& curve) {
  if (curve.IsNull()) return true;
  if (auto c = Handle(Geom2d_TrimmedCurve)::DownCast(curve))
    return finite({c->FirstParameter(), c->LastParameter()}) && finite(c->BasisCurve());
  if (auto c = Handle(Geom2d_OffsetCurve)::DownCast(curve)) return finite({c->Offset()}) && finite(c->BasisCurve());
  if (auto c = Handle(Geom2d_BSplineCurve)::DownCast(curve)) return finitePolesAndWeights(*c) && finiteKnots(*c);
  if (auto c = Handle(Geom2d_BezierCurve)::DownCast(curve)) return finitePolesAndWeights(*c);
  if (auto c = Handle(Geom2d_Line)::DownCast(curve))
    return finite(c->Position().Location()) && finite(c->Position().Direction());
  if (auto c = Handle(Geom2d_Conic)::DownCast(curve)) {
    if (!finite(c->Position())) return false;
    if (auto e = Handle(Geom2d_Circle)::DownCast(c)) return finite({e->Radius()});
    if (auto e = Handle(Geom2d_Ellipse)::DownCast(c)) return finite({e->MajorRadius(), e->MinorRadius()});
    if (auto e = Handle(Geom2d_Hyperbola)::DownCast(c)) return finite({e->MajorRadius(), e->MinorRadius()});
    if (auto e = Handle(Geom2d_Parabola)::DownCast(c)) return finite({e->Focal()});
  }
  return true;
}

bool finite(const Handle(Geom_Surface)& surface) {
  if (surface.IsNull()) return true;
  if (auto s = Handle(Geom_RectangularTrimmedSurface)::DownCast(surface)) {
    double u1, u2, v1, v2;
    s->Bounds(u1, u2, v1, v2);
    return finite({u1, u2, v1, v2}) && finite(s->BasisSurface());
  }
  if (auto s = Handle(Geom_OffsetSurface)::DownCast(surface)) return finite({s->Offset()}) && finite(s->BasisSurface());
  if (auto s = Handle(Geom_BSplineSurface)::DownCast(surface)) {
    for (int i = 1; i <= s->NbUPoles(); ++i)
      for (int j = 1; j <= s->NbVPoles(); ++j)
        if (!finite(s->Pole(i, j)) || !finite({s->Weight(i, j)})) return false;
    for (int i = 1; i <= s->NbUKnots(); ++i)
      if (!finite({s->UKnot(i)})) return false;
    for (int j = 1; j <= s->NbVKnots(); ++j)
      if (!finite({s->VKnot(j)})) return false;
    return true;
  }
  if (auto s = Handle(Geom_BezierSurface)::DownCast(surface)) {
    for (int i = 1; i <= s->NbUPoles(); ++i)
      for (int j = 1; j <= s->NbVPoles(); ++j)
        if (!finite(s->Pole(i, j)) || !finite({s->Weight(i, j)})) return false;
    return true;
  }
  if (auto s = Handle(Geom_SurfaceOfLinearExtrusion)::DownCast(surface))
    return finite(s->Direction()) && finite(s->BasisCurve());
  if (auto s = Handle(Geom_SurfaceOfRevolution)::DownCast(surface))
    return finite(s->Location()) && finite(s->Direction()) && finite(s->BasisCurve());
  if (auto s = Handle(Geom_ElementarySurface)::DownCast(surface)) {
    if (!finite(s->Position())) return false;
    if (auto e = Handle(Geom_CylindricalSurface)::DownCast(s)) return finite({e->Radius()});
    if (auto e = Handle(Geom_ConicalSurface)::DownCast(s)) return finite({e->RefRadius(), e->SemiAngle()});
    if (auto e = Handle(Geom_SphericalSurface)::DownCast(s)) return finite({e->Radius()});
    if (auto e = Handle(Geom_ToroidalSurface)::DownCast(s)) return finite({e->MajorRadius(), e->MinorRadius()});
  }
  return true;
}

bool finite(const Handle(Poly_Triangulation)& mesh) {
  if (mesh.IsNull()) return true;
  for (int i = 1; i <= mesh->NbNodes(); ++i)
    if (!finite(mesh->Node(i)) || (mesh->HasUVNodes() && !finite(mesh->UVNode(i)))) return false;
  return true;
}

[[noreturn]] void fail(const std::string& what, const std::string& item, int index) {
  throw InputError(what + " has a non-finite number (NaN or infinity) in the geometry of " + item + " " +
                   std::to_string(index) + ": the file is damaged; export it again from the CAD tool");
}

}  // namespace

void requireFiniteGeometry(const TopoDS_Shape& shape, const std::string& what) {
  if (shape.IsNull()) return;
  if (!finite(shape.Location())) fail(what, "the shape's placement", 1);
  int index = 0;
  for (TopExp_Explorer ex(shape, TopAbs_VERTEX); ex.More(); ex.Next()) {
    const TopoDS_Vertex& v = TopoDS::Vertex(ex.Current());
    ++index;
    if (!finite(BRep_Tool::Pnt(v)) || !finite({BRep_Tool::Tolerance(v)})) fail(what, "vertex", index);
  }
  index = 0;
  for (TopExp_Explorer ex(shape, TopAbs_EDGE); ex.More(); ex.Next()) {
    const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
    ++index;
    TopLoc_Location location;
    double first = 0, last = 0;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(e, location, first, last);
    if (!finite(curve) || !finite(location) || !finite({first, last, BRep_Tool::Tolerance(e)}))
      fail(what, "edge", index);
  }
  index = 0;
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) {
    const TopoDS_Face& f = TopoDS::Face(ex.Current());
    ++index;
    TopLoc_Location location;
    const Handle(Geom_Surface) surface = BRep_Tool::Surface(f, location);
    if (!finite(surface) || !finite(location) || !finite({BRep_Tool::Tolerance(f)})) fail(what, "face", index);
    TopLoc_Location meshLocation;
    if (!finite(BRep_Tool::Triangulation(f, meshLocation)) || !finite(meshLocation))
      fail(what, "the stored triangulation of face", index);
    for (TopExp_Explorer ee(f, TopAbs_EDGE); ee.More(); ee.Next()) {
      double first = 0, last = 0;
      if (!finite(BRep_Tool::CurveOnSurface(TopoDS::Edge(ee.Current()), f, first, last)) || !finite({first, last}))
        fail(what, "an edge curve on face", index);
    }
  }
}

}  // namespace oraclemesh
