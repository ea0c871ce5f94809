// Crossings in closed form: faces on a plane, cylinder, cone, sphere or torus intersected
// with the segment's line, the roots classified by the face's parametric triangles.
#include "domain/brep/BrepSolidImpl.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRep_Tool.hxx>
#include <IntAna_IntLinTorus.hxx>
#include <Poly_Triangulation.hxx>
#include <TopLoc_Location.hxx>
#include <gp_Lin.hxx>

namespace oraclemesh {

void BrepSolid::Impl::findAnalyticSurfaces() {
  analytic.assign(faces.size(), {});
  for (size_t f = 0; f < faces.size(); ++f) {
    // The closed form classifies its solutions by the face's parametric triangles.
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull() || !tri->HasUVNodes()) continue;
    const BRepAdaptor_Surface surface(faces[f], Standard_True);  // location applied
    AnalyticSurface& s = analytic[f];
    switch (surface.GetType()) {
      case GeomAbs_Plane:
        s.kind = AnalyticSurface::Kind::Plane;
        s.frame = surface.Plane().Position();
        break;
      case GeomAbs_Cylinder:
        s.kind = AnalyticSurface::Kind::Cylinder;
        s.frame = surface.Cylinder().Position();
        s.radius = surface.Cylinder().Radius();
        break;
      case GeomAbs_Cone:
        s.kind = AnalyticSurface::Kind::Cone;
        s.frame = surface.Cone().Position();
        s.radius = surface.Cone().RefRadius();
        s.semiAngle = surface.Cone().SemiAngle();
        s.tanAngle = std::tan(s.semiAngle);
        s.cosAngle = std::cos(s.semiAngle);
        break;
      case GeomAbs_Sphere:
        s.kind = AnalyticSurface::Kind::Sphere;
        s.frame = surface.Sphere().Position();
        s.radius = surface.Sphere().Radius();
        break;
      case GeomAbs_Torus:
        s.kind = AnalyticSurface::Kind::Torus;
        s.torus = surface.Torus();
        s.frame = s.torus.Position();
        s.radius = s.torus.MajorRadius();
        s.minorRadius = s.torus.MinorRadius();
        break;
      default:
        break;
    }
  }
  std::vector<std::vector<CGAL::Bbox_3>> boxesOfFace(faces.size());
  std::vector<std::vector<int>> trianglesOfFace(faces.size());
  std::vector<CGAL::Bbox_3> newtonBoxes;
  std::vector<int> newtonTriangles;
  for (size_t id = 0; id < proxyFaceOfTriangle.size(); ++id) {
    const int f = proxyFaceOfTriangle[id];
    const double m = crossingBand[f];
    const CGAL::Bbox_3& b = proxyTriangleBox[id];
    const CGAL::Bbox_3 grown(b.xmin() - m, b.ymin() - m, b.zmin() - m, b.xmax() + m, b.ymax() + m, b.zmax() + m);
    if (analytic[f].kind == AnalyticSurface::Kind::None) {
      newtonBoxes.push_back(grown);
      newtonTriangles.push_back(static_cast<int>(id));
    } else {
      boxesOfFace[f].push_back(grown);
      trianglesOfFace[f].push_back(static_cast<int>(id));
    }
  }
  analyticFaceTree.resize(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    if (analytic[f].kind == AnalyticSurface::Kind::None) continue;
    // The parameters the closed form gives must be the face's own (they are unless the
    // location scales or mirrors the surface): checked at the triangulation's nodes.
    const AnalyticSurface& s = analytic[f];
    bool agrees = !trianglesOfFace[f].empty();  // else no triangles to classify with
    for (int id : trianglesOfFace[f])
      for (const gp_Pnt& node : newtonTriangle[id].node) {
        const gp_XYZ local = node.XYZ() - s.frame.Location().XYZ();
        double u, v;
        gp_XYZ normal;
        if (!s.parameters(local.Dot(s.frame.XDirection().XYZ()), local.Dot(s.frame.YDirection().XYZ()),
                          local.Dot(s.frame.Direction().XYZ()), classifyTolerance, u, v, normal))
          continue;
        if (faceSurface[f]->Value(u, v).Distance(node) > 1e-6 * diagonal + 2 * maxShapeTolerance) agrees = false;
      }
    if (!agrees) {
      analytic[f].kind = AnalyticSurface::Kind::None;  // Newton iteration answers instead
      for (size_t i = 0; i < trianglesOfFace[f].size(); ++i) {
        newtonBoxes.push_back(boxesOfFace[f][i]);
        newtonTriangles.push_back(trianglesOfFace[f][i]);
      }
      continue;
    }
    analyticFaceTree[f].build(std::move(boxesOfFace[f]), std::move(trianglesOfFace[f]));
    analyticFaces.push_back(static_cast<int>(f));
  }
  newtonFaceTree.build(std::move(newtonBoxes), std::move(newtonTriangles));
}

bool BrepSolid::Impl::analyticCrossings(const Point3& a, const Point3& d, double length, int f,
                                        std::vector<LineHit>& found, std::vector<size_t>& near,
                                        FaceIntersectors& lease) const {
  const AnalyticSurface& s = analytic[f];
  using Kind = AnalyticSurface::Kind;
  const gp_XYZ X = s.frame.XDirection().XYZ(), Y = s.frame.YDirection().XYZ(), Z = s.frame.Direction().XYZ();
  const gp_XYZ dir = gp_XYZ(d[0], d[1], d[2]) / length;
  const gp_XYZ o = gp_XYZ(a[0], a[1], a[2]) - s.frame.Location().XYZ();
  // The line in the surface's frame: (ox, oy, oz) + w (dx, dy, dz), w the distance from a.
  const double ox = o.Dot(X), oy = o.Dot(Y), oz = o.Dot(Z);
  const double dx = dir.Dot(X), dy = dir.Dot(Y), dz = dir.Dot(Z);
  const double tolerance = classifyTolerance;
  std::array<double, 4> roots;
  int rootCount = 0;
  // Roots of A w^2 + B w + C (A != 0), without cancellation; none when the line misses (a
  // tangent line's double root is a touch, dropped like OpenCASCADE's tangent points).
  auto quadratic = [&](double A, double B, double C) {
    const double discriminant = B * B - 4 * A * C;
    if (discriminant < 0) return;
    const double q = -0.5 * (B + std::copysign(std::sqrt(discriminant), B));
    if (q != 0) {
      roots[rootCount++] = q / A;
      roots[rootCount++] = C / q;
    } else {
      roots[rootCount++] = 0;  // B = C = 0: a double root at a, an end crossing
    }
  };
  switch (s.kind) {
    case Kind::Plane:
      if (std::abs(dz) <= 1e-12) {
        if (std::abs(oz) <= tolerance) return false;  // the line lies in the plane
        break;
      }
      roots[rootCount++] = -oz / dz;
      break;
    case Kind::Cylinder: {
      const double A = dx * dx + dy * dy;
      if (A <= 1e-24) {  // along the axis
        if (std::abs(std::hypot(ox, oy) - s.radius) <= tolerance) return false;
        break;
      }
      quadratic(A, 2 * (ox * dx + oy * dy), ox * ox + oy * oy - s.radius * s.radius);
      break;
    }
    case Kind::Sphere:
      quadratic(1, 2 * (ox * dx + oy * dy + oz * dz), ox * ox + oy * oy + oz * oz - s.radius * s.radius);
      break;
    case Kind::Cone: {
      // x^2 + y^2 = r(z)^2 with r(z) = R + z tan(half-angle), both nappes.
      const double k = s.tanAngle, r0 = s.radius + oz * k;
      const double A = dx * dx + dy * dy - dz * dz * k * k;
      if (std::abs(A) <= 1e-12) return false;  // along a generator
      quadratic(A, 2 * (ox * dx + oy * dy - r0 * dz * k), ox * ox + oy * oy - r0 * r0);
      break;
    }
    case Kind::Torus: {
      const IntAna_IntLinTorus intersection(gp_Lin(gp_Pnt(a[0], a[1], a[2]), gp_Dir(dir)), s.torus);
      if (!intersection.IsDone()) return false;
      const double R2 = s.radius * s.radius, r2 = s.minorRadius * s.minorRadius;
      for (int i = 1; i <= intersection.NbPoints() && rootCount < 4; ++i) {
        // Polish the quartic's root along the line: F = (|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2).
        double w = intersection.ParamOnLine(i);
        for (int iteration = 0; iteration < 3; ++iteration) {
          const double x = ox + w * dx, y = oy + w * dy, z = oz + w * dz;
          const double sum = x * x + y * y + z * z + R2 - r2;
          const double F = sum * sum - 4 * R2 * (x * x + y * y);
          const double dF = 4 * sum * (x * dx + y * dy + z * dz) - 8 * R2 * (x * dx + y * dy);
          if (dF == 0) break;
          const double step = F / dF;
          if (!std::isfinite(step) || std::abs(step) > 1e-6 * diagonal) break;
          w -= step;
        }
        roots[rootCount++] = w;
      }
      break;
    }
    case Kind::None:
      return false;
  }
  // OpenCASCADE's rounding decides about a crossing at an end of the segment.
  const double endMargin = 100 * tolerance;
  for (int i = 0; i < rootCount; ++i) {
    const double w = roots[i];
    if (w < -endMargin || w > length + endMargin) continue;
    const gp_XYZ point(a[0] + w * dir.X(), a[1] + w * dir.Y(), a[2] + w * dir.Z());
    // The face lies in its triangles' grown boxes; those holding the point are the ones
    // that classify it.
    near.clear();
    analyticFaceTree[f].atPoint(point, [&](int id) { near.push_back(static_cast<size_t>(id)); });
    if (near.empty()) continue;
    if (w <= endMargin || w >= length - endMargin) return false;
    const double x = ox + w * dx, y = oy + w * dy, z = oz + w * dz;
    // The surface normal (gradient of the implicit equation) and the parameters at the root.
    gp_XYZ normal;
    double u, v;
    if (!s.parameters(x, y, z, tolerance, u, v, normal)) return false;
    const double normalLength = normal.Modulus();
    const double lineNormal = (normal.X() * dx + normal.Y() * dy + normal.Z() * dz);
    // A grazing line: its two crossings merge into a touch that OpenCASCADE may call
    // tangent; leave those to it.
    if (!(std::abs(lineNormal) > 1e-3 * normalLength)) return false;
    // Near a boundary chord OpenCASCADE's classification decides (on the boundary, within
    // the tolerance, the crossing may also belong to the neighbour face): its intersector
    // answers for the face. Elsewhere the parametric triangles do.
    const Domain domain = domainByTriangles(gp_Pnt(point), f, u, v, near.data(), near.size());
    if (domain == Domain::Unsure) return false;
    const bool inside = domain == Domain::In;
    if (!inside) continue;
    found.push_back({w, u, v});
  }
  return true;
}

}  // namespace oraclemesh
