#pragma once
// Solids with input angles under 60 degrees (thesis §3.3: where Rule Set T needs more than
// the thesis gives), shared by the unit and pipeline tests of the small-angle report.
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <GC_MakeArcOfCircle.hxx>
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

// A prism of the given height over the circular segment between the chord (0,0)-(chord,0)
// and the arc above it that leaves both chord ends at `angleDeg` to the chord: the corners of
// its top and bottom faces are angles between a line and a curve, which the first chord of a
// sampled arc makes smaller (by half the arc angle it spans). The vertical edges at the chord
// ends have the same dihedral angle.
inline TopoDS_Shape circularSegment(double angleDeg, double chord, double height) {
  const gp_Pnt start(0, 0, 0), end(chord, 0, 0);
  const gp_Vec tangent(std::cos(angleDeg * kDegree), std::sin(angleDeg * kDegree), 0);
  const TopoDS_Edge arc = BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(start, tangent, end).Value()).Edge();
  const TopoDS_Edge line = BRepBuilderAPI_MakeEdge(end, start).Edge();
  const TopoDS_Face base = BRepBuilderAPI_MakeFace(BRepBuilderAPI_MakeWire(arc, line).Wire()).Face();
  return BRepPrimAPI_MakePrism(base, gp_Vec(0, 0, height)).Shape();
}

// A prism of the given height over the region between the x axis (0..length), the line
// x = length (0..rise) and the arc that leaves the origin along the x axis and ends at
// (length, rise): a cusp (zero angle) at the origin, like the corners where part.step's
// curves leave a vertex tangentially.
inline TopoDS_Shape cusp(double length, double rise, double height) {
  const gp_Pnt origin(0, 0, 0), foot(length, 0, 0), top(length, rise, 0);
  const TopoDS_Edge arc = BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(origin, gp_Vec(1, 0, 0), top).Value()).Edge();
  BRepBuilderAPI_MakeWire wire(BRepBuilderAPI_MakeEdge(origin, foot).Edge(), BRepBuilderAPI_MakeEdge(foot, top).Edge());
  wire.Add(arc);
  return BRepPrimAPI_MakePrism(BRepBuilderAPI_MakeFace(wire.Wire()).Face(), gp_Vec(0, 0, height)).Shape();
}

// A 20 x 10 block (prism of the given height along z) whose upper right edge is chamfered: the
// chamfer leaves the top face (y = 10) at x = 16, sloping down at `chamferDeg`. A part resting
// on the top face and reaching past x = 20 closes an outside wedge of `chamferDeg` along the
// chamfer's upper edge (presse_asm.step's nut under solid #14).
inline TopoDS_Shape chamferedBlock(double chamferDeg, double height) {
  BRepBuilderAPI_MakePolygon profile(gp_Pnt(0, 0, 0), gp_Pnt(20, 0, 0), gp_Pnt(20, 10 - 4 * std::tan(chamferDeg * kDegree), 0),
                                     gp_Pnt(16, 10, 0), Standard_False);
  profile.Add(gp_Pnt(0, 10, 0));
  profile.Close();
  return BRepPrimAPI_MakePrism(BRepBuilderAPI_MakeFace(profile.Wire()).Face(), gp_Vec(0, 0, height)).Shape();
}

}  // namespace oraclemesh::test
