// The tessellation proxy: BRepMesh's triangles as one triangle soup, with the measured
// deviation from the B-rep per face (the bands within which the proxy is not trusted) and
// what the crossing search needs per triangle (parameters, tilt, boundary chords).
#include "domain/brep/BrepSolidImpl.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "Error.h"

namespace oraclemesh {

void BrepSolid::Impl::buildProxy(bool tessellate) {
  // A deflection relative to the model size keeps the proxy's triangle count independent of
  // the units; the exact band below follows whatever BRepMesh actually achieved.
  // 2e-4 keeps curved faces' exact bands thin (most Mesh_3 queries are near the surface)
  // at a few thousand triangles for typical parts.
  const double requested = 2e-4 * diagonal;
  if (tessellate) {
    BRepMesh_IncrementalMesh mesher(shape, requested, Standard_False, 0.5, Standard_False);
    (void)mesher;
  }

  bool complete = true;
  // Starts at zero: a planar face's triangles lie on it, and its band then shrinks to the
  // model tolerance (the polygon-versus-curve gaps at its curved edges lie within the band of
  // the curved neighbour face).
  std::vector<double> measuredOfFace(faces.size(), 0.0);
  proxyFaceOfTriangle.clear();
  std::map<std::array<double, 3>, int> nodeIds;  // exact-coordinate identity, for the gap count
  std::map<std::pair<int, int>, int> edgeUse;
  for (size_t f = 0; f < faces.size(); ++f) {
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull() || tri->NbTriangles() == 0) {
      complete = false;
      facesWithoutTriangles.push_back(static_cast<int>(f));
      continue;
    }
    double& measured = measuredOfFace[f];
    measured = std::max(measured, tri->Deflection());
    const gp_Trsf trsf = loc.Transformation();
    const bool reversed = faces[f].Orientation() == TopAbs_REVERSED;
    std::vector<ProxyMesh::Vertex_index> local(tri->NbNodes() + 1);
    std::vector<gp_Pnt> nodes(tri->NbNodes() + 1);
    std::vector<int> ids(tri->NbNodes() + 1);
    for (int n = 1; n <= tri->NbNodes(); ++n) {
      nodes[n] = tri->Node(n).Transformed(trsf);
      // Finite geometry can still evaluate to NaN or overflow; CGAL must not see such points.
      if (!std::isfinite(nodes[n].X()) || !std::isfinite(nodes[n].Y()) || !std::isfinite(nodes[n].Z()))
        throw InputError("input '" + name + "': OpenCASCADE's tessellation of face " + std::to_string(f + 1) +
                         " has a point that is not a finite number; check the solid with Part > Check geometry "
                         "and repair or re-export it");
      local[n] = proxyMesh.add_vertex(KPoint(nodes[n].X(), nodes[n].Y(), nodes[n].Z()));
      auto it = nodeIds.emplace(std::array<double, 3>{nodes[n].X(), nodes[n].Y(), nodes[n].Z()},
                                static_cast<int>(nodeIds.size())).first;
      ids[n] = it->second;
    }
    // Measure the real deviation: the surface at a triangle's parametric centroid and edge
    // midpoints against the flat triangle there. BRepMesh's own figure is an estimate.
    BRepAdaptor_Surface surface(faces[f], Standard_True);
    const Handle(Geom_Surface) exactSurface = BRep_Tool::Surface(faces[f]);
    // One projector per face: a fresh one samples the whole surface on a grid again at every point.
    std::optional<GeomAPI_ProjectPointOnSurf> projector;
    // Nodes on an edge of the triangulation that is not shared by exactly two triangles.
    std::vector<char> boundaryNode(tri->NbNodes() + 1, 0);
    {
      std::map<std::pair<int, int>, int> use;
      for (int t = 1; t <= tri->NbTriangles(); ++t) {
        int a, b, c;
        tri->Triangle(t).Get(a, b, c);
        for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) ++use[{std::min(u, v), std::max(u, v)}];
      }
      for (const auto& [e, n] : use)
        if (n != 2) boundaryNode[e.first] = boundaryNode[e.second] = 1;
    }
    const size_t firstTriangle = newtonTriangle.size();
    std::vector<std::array<int, 3>> keptCorners;  // triangulation nodes of the kept triangles
    for (int t = 1; t <= tri->NbTriangles(); ++t) {
      int a, b, c;
      tri->Triangle(t).Get(a, b, c);
      if (reversed) std::swap(b, c);
      if (ids[a] == ids[b] || ids[b] == ids[c] || ids[a] == ids[c]) continue;  // collapsed at a pole
      const gp_Vec ab(nodes[a], nodes[b]), ac(nodes[a], nodes[c]);
      if (ab.Crossed(ac).Magnitude() <= 1e-30 * diagonal * diagonal) continue;
      // Each triangle gets its own corner vertices: Side_of_triangle_mesh only needs the
      // triangles, and a soup never fails on non-manifold joins between faces.
      proxyMesh.add_face(local[a], local[b], local[c]);
      proxyFaceOfTriangle.push_back(static_cast<int>(f));
      NewtonTriangle& seedTriangle = newtonTriangle.emplace_back();
      seedTriangle.node = {nodes[a], nodes[b], nodes[c]};
      keptCorners.push_back({a, b, c});
      seedTriangle.corner = {a, b, c};
      for (auto [u, v] : {std::pair{ids[a], ids[b]}, std::pair{ids[b], ids[c]}, std::pair{ids[c], ids[a]}})
        ++edgeUse[{std::min(u, v), std::max(u, v)}];
      if (tri->HasUVNodes()) {
        const gp_Pnt2d ua = tri->UVNode(a), ub = tri->UVNode(b), uc = tri->UVNode(c);
        seedTriangle.uv = {ua, ub, uc};
        seedTriangle.regular = true;
        seedTriangle.interior = !boundaryNode[a] && !boundaryNode[b] && !boundaryNode[c];
        const gp_Dir triangleNormal(ab.Crossed(ac));
        // Normals at the corners, the centroid and the edge midpoints (the tilt's samples).
        const std::array<std::array<double, 3>, 7> tiltWeights{
            {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1 / 3., 1 / 3., 1 / 3.}, {.5, .5, 0}, {0, .5, .5}, {.5, 0, .5}}};
        int sense = 0;
        for (const auto& w : tiltWeights) {
          gp_Pnt p;
          gp_Vec du, dv;
          surface.D1(w[0] * ua.X() + w[1] * ub.X() + w[2] * uc.X(), w[0] * ua.Y() + w[1] * ub.Y() + w[2] * uc.Y(), p,
                     du, dv);
          const gp_Vec n = du.Crossed(dv);
          if (n.Magnitude() <= 1e-12 * du.Magnitude() * dv.Magnitude() || n.Magnitude() == 0) {
            seedTriangle.regular = false;  // a singular point: leave it to OpenCASCADE
            break;
          }
          // The triangle's winding may disagree with the parametrisation's, so the first
          // sample sets the sense; a normal turning over within the triangle (a fold) rules
          // the triangle out.
          const double cosine = triangleNormal.Dot(gp_Dir(n));
          if (sense == 0) sense = cosine < 0 ? -1 : 1;
          if (cosine * sense <= 0) {
            seedTriangle.regular = false;
            break;
          }
          seedTriangle.tilt = std::max(seedTriangle.tilt, std::acos(std::min(1.0, cosine * sense)));
        }
        const std::array<std::array<double, 3>, 4> weights{{{1 / 3., 1 / 3., 1 / 3.}, {.5, .5, 0}, {0, .5, .5}, {.5, 0, .5}}};
        for (const auto& w : weights) {
          const gp_Pnt onSurface = surface.Value(w[0] * ua.X() + w[1] * ub.X() + w[2] * uc.X(),
                                                 w[0] * ua.Y() + w[1] * ub.Y() + w[2] * uc.Y());
          const gp_Pnt onTriangle(w[0] * nodes[a].X() + w[1] * nodes[b].X() + w[2] * nodes[c].X(),
                                  w[0] * nodes[a].Y() + w[1] * nodes[b].Y() + w[2] * nodes[c].Y(),
                                  w[0] * nodes[a].Z() + w[1] * nodes[b].Z() + w[2] * nodes[c].Z());
          double deviation = onSurface.Distance(onTriangle);
          // The parametric correspondence only bounds the deviation from above; where the
          // bound is large (strongly non-uniform parametrisations) ask for the true distance,
          // so that a distorted parametrisation does not widen the exact band for nothing.
          if (deviation > requested) {
            if (!projector) {
              double u0, u1, v0, v1;
              exactSurface->Bounds(u0, u1, v0, v1);
              projector.emplace();
              projector->Init(exactSurface, u0, u1, v0, v1);
            }
            projector->Perform(onTriangle);
            if (projector->IsDone() && projector->NbPoints() > 0)
              deviation = std::min(deviation, projector->LowerDistance());
          }
          measured = std::max(measured, deviation);
        }
      }
    }
    // Chords used by one kept triangle only (by triangulation node, so that a seam's two
    // sides stay apart).
    std::map<std::pair<int, int>, int> keptEdgeUse;
    for (const auto& corners : keptCorners)
      for (int k = 0; k < 3; ++k)
        ++keptEdgeUse[{std::min(corners[k], corners[(k + 1) % 3]), std::max(corners[k], corners[(k + 1) % 3])}];
    for (size_t i = 0; i < keptCorners.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const int p = keptCorners[i][k], q = keptCorners[i][(k + 1) % 3];
        newtonTriangle[firstTriangle + i].boundaryEdge[k] = keptEdgeUse[{std::min(p, q), std::max(p, q)}] == 1;
      }
  }
  // Ray parity only needs every tessellation edge to be used an even number of times (a
  // closed surface mod 2): BRepMesh sometimes folds a B-spline face onto itself, which uses
  // edges four times and is harmless.
  for (const auto& [edge, uses] : edgeUse)
    if (uses % 2 != 0) ++proxy.unpairedEdges;

  proxy.triangles = proxyFaceOfTriangle.size();
  // Margin for the deviation between sampled points, plus the model's own tolerance (a
  // STEP file's edges may sit that far from their faces).
  // A badly parametrised face deviates more than the rest; keeping its band to itself keeps
  // the exact (slow) queries near that face only.
  faceBand.resize(faces.size());
  patchDeviation.resize(faces.size());
  proxy.deflection = 0;
  for (size_t f = 0; f < faces.size(); ++f) {
    // The face's own tolerance (its edges' and vertices' included), not the model's largest:
    // one sloppy edge (U_Joint_2 has a few at 0.02 mm, most at 4e-4) then widens the
    // exact band near its faces only.
    double tolerance = BRep_Tool::Tolerance(faces[f]);
    for (TopExp_Explorer ex(faces[f], TopAbs_EDGE); ex.More(); ex.Next())
      tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Edge(ex.Current())));
    for (TopExp_Explorer ex(faces[f], TopAbs_VERTEX); ex.More(); ex.Next())
      tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Vertex(ex.Current())));
    const double h = 1.5 * measuredOfFace[f] + tolerance;
    patchDeviation[f] = h;
    proxy.deflection = std::max(proxy.deflection, h);
    faceBand[f] = 2 * h + 1e-9 * diagonal;
  }
  proxy.exactBand = 2 * proxy.deflection + 1e-9 * diagonal;
  // A face without triangles or gaps between faces (rays could slip through) make the
  // proxy unreliable: then every query is answered exactly.
  proxy.usable = complete && proxy.triangles > 0 && proxy.unpairedEdges == 0;
  if (proxy.triangles == 0) return;
  proxyTree = std::make_unique<ProxyTree>(proxyMesh.faces().begin(), proxyMesh.faces().end(), proxyMesh);
  proxyTree->build();
  proxyTree->accelerate_distance_queries();  // built now, so that const queries never build
  if (proxy.usable) proxySide = std::make_unique<ProxySide>(*proxyTree);
  for (ProxyMesh::Face_index f : proxyMesh.faces()) proxyTriangleBox.push_back(proxyTriangle(f).bbox());
  measureCrossingBands();
  measureChordReach();
  findAnalyticSurfaces();
}

void BrepSolid::Impl::measureCrossingBands() {
  crossingBand = faceBand;
  for (size_t f = 0; f < faces.size(); ++f) {
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull()) continue;
    const gp_Trsf trsf = loc.Transformation();
    double sagitta = 0;
    for (TopExp_Explorer ex(faces[f], TopAbs_EDGE); ex.More(); ex.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(ex.Current());
      if (BRep_Tool::Degenerated(edge)) continue;
      TopLoc_Location edgeLoc;
      const Handle(Poly_PolygonOnTriangulation) polygon = BRep_Tool::PolygonOnTriangulation(edge, tri, edgeLoc);
      if (polygon.IsNull() || polygon->Parameters().IsNull()) {
        sagitta = std::max(sagitta, proxy.deflection);  // unknown: assume the worst measured
        continue;
      }
      const BRepAdaptor_Curve curve(edge);
      const TColStd_Array1OfInteger& nodes = polygon->Nodes();
      const TColStd_Array1OfReal& parameters = polygon->Parameters()->Array1();
      for (int i = nodes.Lower(); i < nodes.Upper(); ++i) {
        const gp_Pnt p0 = tri->Node(nodes(i)).Transformed(trsf), p1 = tri->Node(nodes(i + 1)).Transformed(trsf);
        const gp_Pnt chordMiddle((p0.XYZ() + p1.XYZ()) / 2);
        const gp_Pnt onCurve = curve.Value(0.5 * (parameters(i) + parameters(i + 1)));
        sagitta = std::max(sagitta, chordMiddle.Distance(onCurve));
      }
    }
    // The midpoint sample bounds the sagitta of a circle-like arc up to sampling: 1.5 keeps
    // a margin as in the face bands.
    crossingBand[f] = faceBand[f] + 1.5 * sagitta;
  }
  maxCrossingBand = crossingBand.empty() ? 0.0 : *std::max_element(crossingBand.begin(), crossingBand.end());
}

Kernel::Triangle_3 BrepSolid::Impl::proxyTriangle(ProxyMesh::Face_index f) const {
  const auto he = proxyMesh.halfedge(f);
  return Kernel::Triangle_3(proxyMesh.point(proxyMesh.source(he)), proxyMesh.point(proxyMesh.target(he)),
                            proxyMesh.point(proxyMesh.target(proxyMesh.next(he))));
}

}  // namespace oraclemesh
