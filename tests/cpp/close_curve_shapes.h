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

}  // namespace oraclemesh::test
