// Shapes from STEP, IGES and BREP files, and from BREP text.
#include "domain/brep/ShapeFiles.h"

#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <StepData_StepModel.hxx>
#include <StepGeom_CartesianPoint.hxx>
#include <StepGeom_Direction.hxx>
#include <TColStd_HArray1OfReal.hxx>
#include <Standard_Failure.hxx>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "Error.h"
#include "domain/BrepSolid.h"

namespace oraclemesh {

namespace {

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || path.find_first_of("/\\", dot) != std::string::npos) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool finiteNumbers(const Handle(TColStd_HArray1OfReal)& values) {
  if (values.IsNull()) return true;
  for (int i = values->Lower(); i <= values->Upper(); ++i)
    if (!std::isfinite(values->Value(i))) return false;
  return true;
}

// The points and directions of a STEP file are checked before the transfer evaluates them: on
// a NaN or infinite coordinate OpenCASCADE's shape healing loops in the transfer.
void requireFiniteStepPoints(const STEPControl_Reader& reader, const std::string& what) {
  const Handle(StepData_StepModel) model = reader.StepModel();
  if (model.IsNull()) return;
  for (int i = 1; i <= model->NbEntities(); ++i) {
    const Handle(Standard_Transient) entity = model->Value(i);
    bool finite = true;
    // Coordinates() would copy three values whatever NbCoordinates() is (and throw for 2D points).
    if (auto point = Handle(StepGeom_CartesianPoint)::DownCast(entity)) {
      for (int k = 1; k <= point->NbCoordinates(); ++k) finite = finite && std::isfinite(point->CoordinatesValue(k));
    } else if (auto direction = Handle(StepGeom_Direction)::DownCast(entity))
      finite = finiteNumbers(direction->DirectionRatios());
    if (!finite)
      throw InputError(what + " has a coordinate that is not a finite number (NaN or infinity) in entity #" +
                       std::to_string(model->IdentLabel(entity)) + ": the file is damaged; export it again from the CAD tool");
  }
}

}  // namespace

TopoDS_Shape readShapeFile(const std::string& path, const std::string& what) {
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
      throw InputError(what + " cannot be read: the file does not exist or is not readable; check the path");
  }
  const std::string ext = lowerExtension(path);
  TopoDS_Shape shape;
  try {
    if (ext == "step" || ext == "stp") {
      STEPControl_Reader reader;
      if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
        throw InputError(what + " is not a readable STEP file: export it again as STEP AP203/AP214 from the CAD tool");
      requireFiniteStepPoints(reader, what);
      if (reader.TransferRoots() == 0)
        throw InputError(what + " holds no shape OpenCASCADE can transfer: export it again as STEP AP203/AP214");
      shape = reader.OneShape();
    } else if (ext == "iges" || ext == "igs") {
      IGESControl_Reader reader;
      if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
        throw InputError(what + " is not a readable IGES file: export it again (IGES 5.3, or better STEP) from the CAD tool");
      if (reader.TransferRoots() == 0)
        throw InputError(what + " holds no shape OpenCASCADE can transfer: export it again as IGES 5.3 or STEP");
      shape = reader.OneShape();
    } else if (ext == "brep" || ext == "brp") {
      BRep_Builder builder;
      if (!BRepTools::Read(shape, path.c_str(), builder) || shape.IsNull())
        throw InputError(what + " is not a readable BREP file: write it again with Part > Export (*.brep)");
    } else {
      throw InputError(what + " has an unsupported file type '." + ext +
                       "': give a STEP (.step, .stp), IGES (.iges, .igs) or BREP (.brep, .brp) file");
    }
  } catch (const Standard_Failure& failure) {
    throw InputError(what + " could not be read (" + std::string(failure.GetMessageString()) +
                     "): export it again from the CAD tool");
  }
  return shape;
}

TopoDS_Shape readBrepText(const std::string& text, const std::string& what, const std::string& fix) {
  TopoDS_Shape shape;
  try {
    std::istringstream stream(text);
    BRep_Builder builder;
    BRepTools::Read(shape, stream, builder);
  } catch (const Standard_Failure& failure) {
    throw InputError(what + " cannot be read by OpenCASCADE (" + std::string(failure.GetMessageString()) + ")" + fix);
  }
  if (shape.IsNull()) throw InputError(what + " cannot be read by OpenCASCADE" + fix);
  return shape;
}

}  // namespace oraclemesh
