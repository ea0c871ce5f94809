#pragma once
// Reading STEP, IGES and BREP files (internal to domain/brep; readBrepText, for BREP text,
// is declared in domain/BrepSolid.h).
#include <TopoDS_Shape.hxx>

#include <string>

namespace oraclemesh {

// Reads a STEP, IGES or BREP file (by its extension) into one shape; InputError starting
// with `what` for a missing, unreadable or unsupported file.
TopoDS_Shape readShapeFile(const std::string& path, const std::string& what);

}  // namespace oraclemesh
