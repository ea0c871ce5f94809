#pragma once
// From the shape a user gave to the solids of one input (internal to domain/brep): closed
// shells and loose faces that sew into closed shells become solids, open shells are left out
// or rejected, and every remaining solid must enclose a volume. Errors are InputErrors that
// start with `what` ("input 'name'", with the file when there is one).
#include <TopoDS_Shape.hxx>
#include <TopoDS_Solid.hxx>

#include <string>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

// The box of the exact geometry (not of an old tessellation); empty for a void shape.
Bbox boxOf(const TopoDS_Shape& shape);
// Volume of a solid: negative when its faces are oriented inward.
double signedVolume(const TopoDS_Shape& solid);

// The solids of one input in file order, and the open shells left out of it.
struct SolidPieces {
  std::vector<TopoDS_Solid> solids;  // each oriented outward
  std::vector<double> volumes;       // of each solid, as the check measured it
  std::vector<std::string> skipped;  // what was left out: "open shell (item 17 of 18, 3 faces, ...)"
};

// Solids that passed the checks below, as one shape, with their volume: measuring it again
// (BRepGProp over every face) costs about what the checks did.
struct ValidatedSolids {
  TopoDS_Shape shape;
  double volume = 0;
};

// Turns whatever the user gave into solids, or explains why not. Policy for open shells
// (surfaces that bound no volume): beside at least one solid they are left out with a warning
// naming them (assemblies from CAD tools carry stray sheets, e.g. presse_asm.step); when
// nothing solid remains the input is an error. A solid whose own boundary is open is always
// an error: the user meant it to be a volume, and leaving it out would change the model.
SolidPieces solidPieces(const TopoDS_Shape& input, const std::string& what);
// One solid as itself, several as a compound.
TopoDS_Shape compoundOf(const std::vector<TopoDS_Solid>& solids);
// Solids [first, last) of `pieces` as one input.
ValidatedSolids validatedPart(const SolidPieces& pieces, size_t first, size_t last);
// The constructor's check: every part of the shape must be a volume. Loaders that may leave
// open shells out (with a warning) split the shape first and pass only its solids.
ValidatedSolids validatedSolids(const TopoDS_Shape& input, const std::string& what);

}  // namespace oraclemesh
