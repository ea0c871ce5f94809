#include "domain/brep/ToleranceCheck.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRep_Tool.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
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

// The first edge of `solid` whose curve ends farther from its vertex than the tolerances allow.
void requireEdgesEndAtTheirVertices(const TopoDS_Solid& solid, double diagonal, const std::string& where) {
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(solid, TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i) {
    const TopoDS_Edge edge = TopoDS::Edge(edges(i).Oriented(TopAbs_FORWARD));
    if (BRep_Tool::Degenerated(edge) || !BRep_Tool::IsGeometric(edge)) continue;
    TopoDS_Vertex first, last;
    TopExp::Vertices(edge, first, last);
    if (first.IsNull() || last.IsNull()) continue;
    const BRepAdaptor_Curve curve(edge);
    for (const auto& [vertex, parameter] : {std::make_pair(first, curve.FirstParameter()),
                                            std::make_pair(last, curve.LastParameter())}) {
      const gp_Pnt end = curve.Value(parameter), at = BRep_Tool::Pnt(vertex);
      const double tolerance = std::max(BRep_Tool::Tolerance(vertex), BRep_Tool::Tolerance(edge));
      const double gap = end.Distance(at);
      if (gap <= std::max(2 * tolerance, kLargestRelativeEndGap * diagonal)) continue;
      char text[200];
      std::snprintf(text, sizeof text, " whose curve ends at %s, %g model units from its vertex at %s (tolerance %g)",
                    pointText(end).c_str(), gap, pointText(at).c_str(), tolerance);
      throw InputError(where + "edge " + std::to_string(i) + " of " + std::to_string(edges.Extent()) + text +
                       ": the file is damaged there (a number of the edge's curve or range changed); check it with "
                       "Part > Check geometry, repair it or export it again from the CAD tool");
    }
  }
}

}  // namespace

void requireConsistentTolerances(const std::vector<TopoDS_Solid>& solids, const std::string& what) {
  for (size_t k = 0; k < solids.size(); ++k) {
    const double diagonal = boxOf(solids[k]).diagonal();
    const std::string solid =
        solids.size() > 1 ? "solid " + std::to_string(k + 1) + " of " + std::to_string(solids.size()) + ", " : "";
    Widest widest;
    // Edges first: a vertex is at least as wide as its edges, and the edge is what the user
    // finds and repairs.
    widen(widest, solids[k], TopAbs_EDGE);
    if (!(widest.tolerance > kLargestRelativeTolerance * diagonal)) widen(widest, solids[k], TopAbs_VERTEX);
    if (!(widest.tolerance > kLargestRelativeTolerance * diagonal)) widen(widest, solids[k], TopAbs_FACE);
    if (!(widest.tolerance > kLargestRelativeTolerance * diagonal)) {
      requireEdgesEndAtTheirVertices(solids[k], diagonal, what + " has " + (solid.empty() ? "" : "in " + solid));
      continue;
    }
    char size[160];
    std::snprintf(size, sizeof size, " has a tolerance of %g model units, %.3g %% of the solid's size (%g across)",
                  widest.tolerance, 100 * widest.tolerance / diagonal, diagonal);
    throw InputError(what + ": " + solid + describe(widest) + size +
                     ": OpenCASCADE widened it to bridge a gap the file leaves between an edge and its faces "
                     "(a face whose surface does not carry its edges), so the file is damaged there and a mesh "
                     "would join points that far apart; check it with Part > Check geometry, repair it or export it "
                     "again from the CAD tool");
  }
}

}  // namespace oraclemesh
