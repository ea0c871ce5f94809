#pragma once
// OpenCASCADE-based measurements shared by the C++ tests: where the shared CAD models are,
// exact distances to B-rep boundaries, volumes, BREP text.
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "Geometry.h"

namespace oraclemesh::test {

// ../shared/data/cad beside the repository; tests/run.sh and CMake set ORACLEMESH_CAD_DIR.
inline std::string cadDir() {
  const char* dir = std::getenv("ORACLEMESH_CAD_DIR");
  return dir && *dir ? dir : "../shared/data/cad";
}

// Distance to the boundary of `shape`: BRepExtrema reports 0 for points inside a solid,
// so solids are measured through their faces.
inline double distanceToShape(const Point3& p, const TopoDS_Shape& shape) {
  TopoDS_Shape target = shape;
  if (shape.ShapeType() <= TopAbs_SOLID) {
    BRep_Builder builder;
    TopoDS_Compound faces;
    builder.MakeCompound(faces);
    for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) builder.Add(faces, ex.Current());
    target = faces;
  }
  BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(gp_Pnt(p[0], p[1], p[2])).Vertex(), target);
  EXPECT_TRUE(dist.IsDone());
  return dist.Value();
}

// What FreeCAD's Shape.exportBrepToString() gives: the job's "brep" input.
// The shapes as one compound, in the given order (how multi-solid files are built).
inline TopoDS_Compound compoundOf(std::initializer_list<TopoDS_Shape> shapes) {
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  for (const TopoDS_Shape& s : shapes) builder.Add(compound, s);
  return compound;
}

inline std::string brepText(const TopoDS_Shape& shape) {
  std::ostringstream out;
  BRepTools::Write(shape, out);
  return out.str();
}

inline double volumeOf(const TopoDS_Shape& shape) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(shape, props);
  return props.Mass();
}

// An ASCII STL of the shape's BRepMesh tessellation (BRepMesh_IncrementalMesh first), each
// face's triangles turned with it; full precision, so nodes shared by faces stay shared.
inline void writeTessellationStl(const TopoDS_Shape& shape, const std::string& path) {
  std::ofstream out(path);
  out.precision(17);
  out << "solid tessellation\n";
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) {
    const TopoDS_Face& face = TopoDS::Face(ex.Current());
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    ASSERT_FALSE(tri.IsNull());
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (int t = 1; t <= tri->NbTriangles(); ++t) {
      int n[3];
      tri->Triangle(t).Get(n[0], n[1], n[2]);
      if (reversed) std::swap(n[1], n[2]);
      out << "facet normal 0 0 0\n outer loop\n";
      for (int k : n) {
        const gp_Pnt p = tri->Node(k).Transformed(loc.Transformation());
        out << "  vertex " << p.X() << " " << p.Y() << " " << p.Z() << "\n";
      }
      out << " endloop\nendfacet\n";
    }
  }
  out << "endsolid tessellation\n";
}

}  // namespace oraclemesh::test
