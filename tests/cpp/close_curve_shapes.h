#pragma once
// Parts in contact along a circle, as in presse_asm.step: a pin standing in the hole of a
// plate, flush with the plate's bottom face. The hole's bottom edge and the pin's bottom edge
// are the same circle, but their B-rep vertices (seams) are 37 degrees apart, so the two
// solids sample it at different points and the two chords cross each other.
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>

#include <cmath>
#include <vector>

namespace oraclemesh::test {

constexpr double kPinRadius = 10, kPlateThickness = 10, kPinLength = 20;

// {plate, pin}, the plate first (its priority does not matter: they do not overlap).
inline std::vector<TopoDS_Shape> plateWithPin() {
  const gp_Dir up(0, 0, 1);
  const double seam = 37.0 * 3.14159265358979323846 / 180;
  const TopoDS_Shape hole = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), up), kPinRadius, kPlateThickness).Shape();
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(-30, -30, 0), 60, 60, kPlateThickness).Shape();
  return {BRepAlgoAPI_Cut(box, hole).Shape(),
          BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), up, gp_Dir(std::cos(seam), std::sin(seam), 0)), kPinRadius,
                                   kPinLength)
              .Shape()};
}

// As at presse_asm.step's circle r = 12, y = 188.5: a rod (first priority) stands in the bore
// of a block and goes on through a nut under it, whose top face is flush with the block's
// bottom face. The bore's bottom edge (a sharp edge of the block) and the junction where the rod
// leaves the nut's top face are the same circle, and a crease: rod, block and nut meet there.
// {rod, block, nut}.
constexpr double kRodRadius = 12;

inline std::vector<TopoDS_Shape> rodThroughBoreOntoNut() {
  const gp_Dir up(0, 0, 1);
  const TopoDS_Shape bore = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), up), kRodRadius, 30).Shape();
  const TopoDS_Shape block = BRepPrimAPI_MakeBox(gp_Pnt(-30, -30, 0), 60, 60, 30).Shape();
  return {BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -25), up), kRodRadius, 45).Shape(),
          BRepAlgoAPI_Cut(block, bore).Shape(), BRepPrimAPI_MakeBox(gp_Pnt(-20, -20, -15), 40, 40, 15).Shape()};
}

}  // namespace oraclemesh::test
