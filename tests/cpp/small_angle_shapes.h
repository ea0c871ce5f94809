#pragma once
// Solids with input angles under 60 degrees (thesis §3.3: where Rule Set T needs more than
// the thesis gives), shared by the unit and pipeline tests of the small-angle report.
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <gp_Ax2.hxx>

#include <cmath>

namespace oraclemesh::test {

constexpr double kDegree = 3.14159265358979323846 / 180;

// A prism over the triangle (0,0) (length,0) (length, length tan(angle)) of the given height:
// the edge along z through the origin has the dihedral angle `angleDeg`, and at both of its
// ends two feature edges meet at `angleDeg`. Its other dihedral angles are 90 and 90 - angle.
inline TopoDS_Shape wedge(double angleDeg, double length, double height, const gp_Pnt& origin = gp_Pnt(0, 0, 0)) {
  BRepBuilderAPI_MakePolygon triangle(
      origin, gp_Pnt(origin.X() + length, origin.Y(), origin.Z()),
      gp_Pnt(origin.X() + length, origin.Y() + length * std::tan(angleDeg * kDegree), origin.Z()), Standard_True);
  return BRepPrimAPI_MakePrism(BRepBuilderAPI_MakeFace(triangle.Wire()).Face(), gp_Vec(0, 0, height)).Shape();
}

// A cone standing on its base at `base`, apex up: opening angle 2 atan(radius / height).
inline TopoDS_Shape coneWithTip(const gp_Pnt& base, double radius, double height) {
  return BRepPrimAPI_MakeCone(gp_Ax2(base, gp_Dir(0, 0, 1)), radius, 0, height).Shape();
}

}  // namespace oraclemesh::test
