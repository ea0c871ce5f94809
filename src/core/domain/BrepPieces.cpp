#include "domain/BrepPieces.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepClass3d.hxx>
#include <BRep_Tool.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shell.hxx>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <vector>

namespace oraclemesh {

namespace {

struct EdgeShape {
  gp_Pnt middle;
  double length = 0;
  double tolerance = 0;
};

// Edges that lie on another edge: where two pieces touch, OpenCASCADE may give each piece its
// own copy of the edge, each shared by two faces that belong to different pieces.
std::vector<bool> edgesOnAnotherEdge(const BrepTopology& brep) {
  std::vector<EdgeShape> shapes(brep.edgeCount());
  for (int e = 0; e < brep.edgeCount(); ++e) {
    const TopoDS_Edge& edge = brep.edge(e);
    if (BRep_Tool::Degenerated(edge)) continue;
    const BRepAdaptor_Curve curve(edge);
    shapes[e] = {curve.Value(0.5 * (curve.FirstParameter() + curve.LastParameter())),
                 GCPnts_AbscissaPoint::Length(curve), BRep_Tool::Tolerance(edge)};
  }
  std::vector<int> byX(shapes.size());
  std::iota(byX.begin(), byX.end(), 0);
  std::sort(byX.begin(), byX.end(), [&](int a, int b) { return shapes[a].middle.X() < shapes[b].middle.X(); });
  double widest = 0;
  for (const EdgeShape& s : shapes) widest = std::max(widest, s.tolerance);
  std::vector<bool> onAnother(shapes.size(), false);
  for (size_t i = 0; i < byX.size(); ++i) {
    const EdgeShape& a = shapes[byX[i]];
    if (a.length <= 0) continue;
    for (size_t j = i + 1; j < byX.size(); ++j) {
      const EdgeShape& b = shapes[byX[j]];
      if (b.middle.X() - a.middle.X() > 2 * widest) break;
      const double tolerance = a.tolerance + b.tolerance;
      if (b.length > 0 && a.middle.Distance(b.middle) <= tolerance && std::abs(a.length - b.length) <= tolerance)
        onAnother[byX[i]] = onAnother[byX[j]] = true;
    }
  }
  return onAnother;
}

}  // namespace

int volumePiecesAtMost(const BrepTopology& brep) {
  std::vector<int> group(brep.faceCount());
  std::iota(group.begin(), group.end(), 0);
  auto root = [&](int f) {
    while (group[f] != f) f = group[f] = group[group[f]];
    return f;
  };
  const std::vector<bool> onAnother = edgesOnAnotherEdge(brep);
  for (int e = 0; e < brep.edgeCount(); ++e) {
    const std::vector<int>& faces = brep.facesOfEdge(e);
    if (faces.size() == 2 && !onAnother[e]) group[root(faces[0])] = root(faces[1]);
  }
  TopTools_IndexedMapOfShape faceIndex;
  TopExp::MapShapes(brep.shape(), TopAbs_FACE, faceIndex);
  std::set<int> outerGroups;
  for (TopExp_Explorer solid(brep.shape(), TopAbs_SOLID); solid.More(); solid.Next()) {
    const TopoDS_Shell outer = BRepClass3d::OuterShell(TopoDS::Solid(solid.Current()));
    for (TopExp_Explorer face(outer, TopAbs_FACE); face.More(); face.Next()) {
      const int index = faceIndex.FindIndex(face.Current());
      if (index > 0) outerGroups.insert(root(index - 1));
    }
  }
  return static_cast<int>(outerGroups.size());
}

}  // namespace oraclemesh
