// Solid checks: sewing, closed shells made solid, open shells and zero volumes reported.
#include "domain/brep/SolidChecks.h"

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepGProp.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <ShapeFix_Solid.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Shell.hxx>

#include <algorithm>
#include <cstdint>
#include <sstream>

#include "Error.h"
#include "domain/brep/FiniteGeometry.h"
#include "domain/brep/ToleranceCheck.h"

namespace oraclemesh {

namespace {

std::string plural(int64_t n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// Edges bounding a single face of `shape`: holes in the surface. Degenerated edges (cone
// apex, sphere pole) and seams (the same face on both sides) are not holes.
int64_t countFreeEdges(const TopoDS_Shape& shape) {
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  int64_t freeEdges = 0;
  for (int i = 1; i <= edgeFaces.Extent(); ++i) {
    const TopoDS_Edge& e = TopoDS::Edge(edgeFaces.FindKey(i));
    if (BRep_Tool::Degenerated(e)) continue;
    const TopTools_ListOfShape& faces = edgeFaces.FindFromIndex(i);
    TopTools_IndexedMapOfShape distinct;
    for (const TopoDS_Shape& f : faces) distinct.Add(f);
    if (distinct.Extent() != 1) continue;
    if (BRep_Tool::IsClosed(e, TopoDS::Face(distinct(1)))) continue;
    ++freeEdges;
  }
  return freeEdges;
}

// Sews the faces of `shape` with a tolerance relative to the model size: shells that are
// closed up to tiny gaps (typical of STEP export) become closed.
TopoDS_Shape sewFaces(const TopoDS_Shape& shape, double tolerance) {
  BRepBuilderAPI_Sewing sewing(tolerance);
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) sewing.Add(ex.Current());
  sewing.Perform();
  return sewing.SewedShape();
}

TopoDS_Solid solidFromClosedShell(const TopoDS_Shell& shell) {
  // SolidFromShell builds the solid and orients its shell so that the volume is positive
  // (outward face normals), which BRepBuilderAPI_MakeSolid alone does not guarantee.
  ShapeFix_Solid fix;
  return fix.SolidFromShell(shell);
}

// Walks compounds depth first so that solids and shells come out in the order the file (or
// FreeCAD's compound) lists them: that order is the priority of per-solid inputs.
void collectPieces(const TopoDS_Shape& shape, std::vector<TopoDS_Shape>& items, TopoDS_Compound& looseFaces,
                   int64_t& looseFaceCount) {
  switch (shape.ShapeType()) {
    case TopAbs_COMPOUND:
    case TopAbs_COMPSOLID:
      for (TopoDS_Iterator it(shape); it.More(); it.Next())
        collectPieces(it.Value(), items, looseFaces, looseFaceCount);
      break;
    case TopAbs_SOLID:
    case TopAbs_SHELL:
      items.push_back(shape);
      break;
    case TopAbs_FACE: {
      BRep_Builder builder;
      builder.Add(looseFaces, shape);
      ++looseFaceCount;
      break;
    }
    default:
      break;  // wires, edges and vertices bound no volume; counted only if nothing else is found
  }
}

std::string near(const TopoDS_Shape& shape) {
  const Bbox b = boxOf(shape);
  std::ostringstream out;
  out.precision(6);
  out << "(" << 0.5 * (b.min[0] + b.max[0]) << ", " << 0.5 * (b.min[1] + b.max[1]) << ", "
      << 0.5 * (b.min[2] + b.max[2]) << ")";
  return out.str();
}

int64_t countFaces(const TopoDS_Shape& shape) {
  int64_t n = 0;
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) ++n;
  return n;
}

}  // namespace

Bbox boxOf(const TopoDS_Shape& shape) {
  Bnd_Box box;
  // useTriangulation=false: the box of the exact geometry, not of an old tessellation.
  BRepBndLib::Add(shape, box, false);
  Bbox b;
  if (box.IsVoid()) return b;
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  b.add(Point3{x0, y0, z0});
  b.add(Point3{x1, y1, z1});
  return b;
}

double signedVolume(const TopoDS_Shape& solid) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props);
  return props.Mass();
}

SolidPieces solidPieces(const TopoDS_Shape& input, const std::string& what) {
  if (input.IsNull())
    throw InputError(what + " holds no geometry: select a solid, or a closed shell");
  requireFiniteGeometry(input, what);  // sewing and the box below evaluate the geometry
  const double sewTolerance = std::max(1e-6 * boxOf(input).diagonal(), 1e-7);

  std::vector<TopoDS_Shape> items;
  BRep_Builder builder;
  TopoDS_Compound faceBag;
  builder.MakeCompound(faceBag);
  int64_t looseFaces = 0;
  collectPieces(input, items, faceBag, looseFaces);

  SolidPieces pieces;
  struct OpenShell {
    size_t item;
    int64_t faces, freeEdges;
    std::string near;
  };
  std::vector<OpenShell> open;
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i].ShapeType() == TopAbs_SOLID) {
      const TopoDS_Solid& solid = TopoDS::Solid(items[i]);
      const int64_t freeEdges = countFreeEdges(solid);
      if (freeEdges > 0)
        throw InputError(what + " has a solid whose boundary is open (" + plural(freeEdges, "free edge") +
                         (items.size() > 1 ? ", item " + std::to_string(i + 1) + " of " + std::to_string(items.size()) +
                                                 " near " + near(solid)
                                           : "") +
                         "): repair the solid (Part > Check geometry, Part > Refine shape) or rebuild it from a "
                         "closed shell");
      pieces.solids.push_back(solid);
      continue;
    }
    TopoDS_Shape closed = items[i];
    if (countFreeEdges(items[i]) > 0) {
      // A shell that only lacks sewing (faces not sharing their edges) is still a closed
      // surface to the user; sewing is what FreeCAD's Shape builder would do.
      closed = sewFaces(items[i], sewTolerance);
      const int64_t sewnFree = countFreeEdges(closed);
      if (sewnFree > 0) {
        open.push_back({i, countFaces(items[i]), sewnFree, near(items[i])});
        continue;
      }
    }
    for (TopExp_Explorer ex(closed, TopAbs_SHELL); ex.More(); ex.Next())
      pieces.solids.push_back(solidFromClosedShell(TopoDS::Shell(ex.Current())));
  }

  // Loose faces (IGES files of trimmed surfaces, exploded shells) are sewn together first.
  bool looseFacesClose = true;
  int looseShells = 0;
  int64_t looseFree = 0;
  if (looseFaces > 0) {
    const TopoDS_Shape sewn = sewFaces(faceBag, sewTolerance);
    looseFree = countFreeEdges(sewn);
    for (TopExp_Explorer ex(sewn, TopAbs_SHELL); ex.More(); ex.Next()) ++looseShells;
    looseFacesClose = looseShells > 0 && looseFree == 0;
    if (looseFacesClose)
      for (TopExp_Explorer ex(sewn, TopAbs_SHELL); ex.More(); ex.Next())
        pieces.solids.push_back(solidFromClosedShell(TopoDS::Shell(ex.Current())));
  }

  if (pieces.solids.empty()) {
    if (open.size() == 1 && items.size() == 1 && looseFaces == 0)
      throw InputError(what + " is an open shell with " + plural(open.front().freeEdges, "free edge") +
                       ": close the surface or sew it (Part > Shape builder)");
    if (!open.empty()) {
      int64_t freeEdges = 0;
      for (const OpenShell& s : open) freeEdges += s.freeEdges;
      throw InputError(what + " holds only open shells (" + std::to_string(open.size()) + " shells with " +
                       plural(freeEdges, "free edge") + " in all) and no solid: close the surfaces or sew them "
                       "(Part > Shape builder)");
    }
    if (looseFaces > 0)
      throw InputError(what + " holds no solid (found " + plural(looseFaces, "face") +
                       (looseShells > 0 ? " that leave " + plural(looseFree, "free edge") + " when sewn" : "") +
                       "): select a solid, or a closed shell");
    int64_t edges = 0, vertices = 0;
    for (TopExp_Explorer ex(input, TopAbs_EDGE); ex.More(); ex.Next()) ++edges;
    for (TopExp_Explorer ex(input, TopAbs_VERTEX); ex.More(); ex.Next()) ++vertices;
    const std::string found = edges > 0 ? plural(edges, "edge") : vertices > 0 ? plural(vertices, "vertex") : "nothing";
    throw InputError(what + " holds no solid (found " + found + "): select a solid, or a closed shell");
  }

  for (const OpenShell& s : open)
    pieces.skipped.push_back("open shell (item " + std::to_string(s.item + 1) + " of " + std::to_string(items.size()) +
                             ", " + plural(s.faces, "face") + ", " + plural(s.freeEdges, "free edge") + ", near " +
                             s.near + ")");
  if (!looseFacesClose)
    pieces.skipped.push_back(plural(looseFaces, "loose face") + " that leave " + plural(looseFree, "free edge") +
                             " when sewn");

  for (TopoDS_Solid& solid : pieces.solids) {
    const double v = signedVolume(solid);
    if (v < 0) solid.Reverse();  // inside out (faces oriented inward): flip it
    if (!(std::abs(v) > 0))
      throw InputError(what + " has a solid with zero volume: select a solid that encloses a volume");
    pieces.volumes.push_back(std::abs(v));
  }
  requireConsistentTolerances(pieces.solids, what);
  return pieces;
}

TopoDS_Shape compoundOf(const std::vector<TopoDS_Solid>& solids) {
  if (solids.size() == 1) return solids.front();
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  for (const TopoDS_Solid& s : solids) builder.Add(compound, s);
  return compound;
}

ValidatedSolids validatedPart(const SolidPieces& pieces, size_t first, size_t last) {
  ValidatedSolids part;
  part.shape = compoundOf({pieces.solids.begin() + first, pieces.solids.begin() + last});
  for (size_t i = first; i < last; ++i) part.volume += pieces.volumes[i];
  return part;
}

ValidatedSolids validatedSolids(const TopoDS_Shape& input, const std::string& what) {
  const SolidPieces pieces = solidPieces(input, what);
  if (!pieces.skipped.empty())
    throw InputError(what + " holds, besides its solids, pieces that bound no volume (first: " + pieces.skipped.front() +
                     "): close them (Part > Shape builder), or leave them out of the input");
  return validatedPart(pieces, 0, pieces.solids.size());
}

}  // namespace oraclemesh
