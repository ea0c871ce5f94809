#include "domain/brep/ToleranceCheck.h"

#include <BRep_Tool.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>

#include <cstdio>

#include "Error.h"
#include "domain/brep/SolidChecks.h"

namespace oraclemesh {

namespace {

struct Widest {
  double tolerance = 0;
  TopAbs_ShapeEnum kind = TopAbs_SHAPE;
  int index = 0, count = 0;  // 1-based within the solid, as FreeCAD numbers Edge1, Vertex1, Face1
  TopoDS_Shape shape;
};

void widen(Widest& widest, const TopoDS_Solid& solid, TopAbs_ShapeEnum kind) {
  TopTools_IndexedMapOfShape items;
  TopExp::MapShapes(solid, kind, items);
  for (int i = 1; i <= items.Extent(); ++i) {
    const TopoDS_Shape& s = items(i);
    const double t = kind == TopAbs_EDGE     ? BRep_Tool::Tolerance(TopoDS::Edge(s))
                     : kind == TopAbs_VERTEX ? BRep_Tool::Tolerance(TopoDS::Vertex(s))
                                             : BRep_Tool::Tolerance(TopoDS::Face(s));
    if (t > widest.tolerance) widest = {t, kind, i, items.Extent(), s};
  }
}

std::string pointText(const gp_Pnt& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%g, %g, %g)", p.X(), p.Y(), p.Z());
  return text;
}

std::string describe(const Widest& w) {
  const std::string numbered = " " + std::to_string(w.index) + " of " + std::to_string(w.count);
  if (w.kind == TopAbs_EDGE) {
    TopoDS_Vertex first, last;
    TopExp::Vertices(TopoDS::Edge(w.shape), first, last);
    std::string text = "edge" + numbered;
    if (!first.IsNull() && !last.IsNull())
      text += ", from " + pointText(BRep_Tool::Pnt(first)) + " to " + pointText(BRep_Tool::Pnt(last)) + ",";
    return text;
  }
  if (w.kind == TopAbs_VERTEX) return "vertex" + numbered + " at " + pointText(BRep_Tool::Pnt(TopoDS::Vertex(w.shape))) + ",";
  return "face" + numbered;
}

}  // namespace

void requireTolerancesWithinModel(const std::vector<TopoDS_Solid>& solids, const std::string& what) {
  for (size_t k = 0; k < solids.size(); ++k) {
    const double diagonal = boxOf(solids[k]).diagonal();
    Widest widest;
    // Edges first: a vertex is at least as wide as its edges, and the edge is what the user
    // finds and repairs.
    widen(widest, solids[k], TopAbs_EDGE);
    if (!(widest.tolerance > kLargestRelativeTolerance * diagonal)) widen(widest, solids[k], TopAbs_VERTEX);
    if (!(widest.tolerance > kLargestRelativeTolerance * diagonal)) widen(widest, solids[k], TopAbs_FACE);
    if (!(widest.tolerance > kLargestRelativeTolerance * diagonal)) continue;
    char size[160];
    std::snprintf(size, sizeof size, " has a tolerance of %g model units, %.3g %% of the solid's size (%g across)",
                  widest.tolerance, 100 * widest.tolerance / diagonal, diagonal);
    const std::string solid =
        solids.size() > 1 ? "solid " + std::to_string(k + 1) + " of " + std::to_string(solids.size()) + ", " : "";
    throw InputError(what + ": " + solid + describe(widest) + size +
                     ": OpenCASCADE widened it to bridge a gap the file leaves between an edge and its faces "
                     "(a face whose surface does not carry its edges), so the file is damaged there and a mesh "
                     "would join points that far apart; check it with Part > Check geometry, repair it or export it "
                     "again from the CAD tool");
  }
}

}  // namespace oraclemesh
