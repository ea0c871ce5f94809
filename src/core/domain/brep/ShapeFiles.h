#pragma once
// Reading STEP, IGES and BREP files (internal to domain/brep; readBrepText, for BREP text,
// is declared in domain/BrepSolid.h).
#include <TopoDS_Shape.hxx>

#include <string>

namespace oraclemesh {

// Reads a STEP, IGES or BREP file (by its extension) into one shape; InputError starting
// with `what` for a missing, unreadable or unsupported file. `declaredUncertainty`, when
// given, receives the largest UNCERTAINTY_MEASURE_WITH_UNIT of a STEP file in the shape's
// length unit (the distance below which the CAD tool took two points as one), 0 for other
// files and STEP files that declare none.
TopoDS_Shape readShapeFile(const std::string& path, const std::string& what, double* declaredUncertainty = nullptr);

// The same declared uncertainty of a STEP file without transferring its shapes (the workbench
// asks it of the file FreeCAD imported an assembly from); InputError starting with `what` when
// the file is no readable STEP file.
double declaredStepUncertainty(const std::string& path, const std::string& what);

}  // namespace oraclemesh
