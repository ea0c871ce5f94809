// Shapes from STEP, IGES and BREP files, and from BREP text.
#include "domain/brep/ShapeFiles.h"

#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <STEPConstruct_UnitContext.hxx>
#include <STEPControl_Reader.hxx>
#include <StepBasic_NamedUnit.hxx>
#include <StepBasic_UncertaintyMeasureWithUnit.hxx>
#include <StepData_StepModel.hxx>
#include <StepGeom_CartesianPoint.hxx>
#include <StepGeom_Direction.hxx>
#include <TColStd_HArray1OfReal.hxx>
#include <Standard_Failure.hxx>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <tuple>
#include <utility>

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

// The largest length uncertainty the file declares (UNCERTAINTY_MEASURE_WITH_UNIT, one per
// representation context, so one per part in an assembly), converted from its unit to the
// unit of the transferred shape; 0 when there is none. OpenCASCADE turns it into no shape
// tolerance (the shapes come back with their own, often 1e-7), so the mesher reads it here.
double largestStepUncertainty(const STEPControl_Reader& reader) {
  const Handle(StepData_StepModel) model = reader.StepModel();
  if (model.IsNull()) return 0;
  double largest = 0;
  for (int i = 1; i <= model->NbEntities(); ++i) {
    const auto measure = Handle(StepBasic_UncertaintyMeasureWithUnit)::DownCast(model->Value(i));
    if (measure.IsNull()) continue;
    const Handle(StepBasic_NamedUnit) unit = measure->UnitComponent().NamedUnit();
    if (unit.IsNull()) continue;
    STEPConstruct_UnitContext units;
    if (units.ComputeFactors(unit) != 0 || !units.LengthDone()) continue;  // not a length
    const double value = measure->ValueComponent() * units.LengthFactor();
    if (std::isfinite(value) && value > largest) largest = value;
  }
  return largest;
}

// What OpenCASCADE failing inside a reader says about the file.
InputError unreadableFile(const std::string& what, const Standard_Failure& failure) {
  return InputError(what + " could not be read (" + std::string(failure.GetMessageString()) +
                    "): export it again from the CAD tool");
}

// Reads the file into `reader`'s STEP model (no shapes transferred yet).
void readStepModel(STEPControl_Reader& reader, const std::string& path, const std::string& what) {
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
    throw InputError(what + " is not a readable STEP file: export it again as STEP AP203/AP214 from the CAD tool");
}

// The parameter delimiter and record delimiter an IGES file declares at the start of its
// global section ("1H," and "1H;", or empty fields for those defaults).
std::pair<char, char> igesDelimiters(const std::string& global) {
  const bool declared = global.compare(0, 2, "1H") == 0 && global.size() > 2;
  const char parameter = declared ? global[2] : ',';
  const size_t second = declared ? 4 : 1;  // past "1Hc" and its delimiter, or the empty field's
  const char record = global.compare(second, 2, "1H") == 0 && global.size() > second + 2 ? global[second + 2] : ';';
  return {parameter, record};
}

// A parameter that reads as a real number (IGES writes 1.5D3 as well as 1.5E3) but is not
// finite: "1.D999" overflows to infinity, "NaN" is one.
bool nonFiniteReal(std::string token) {
  if (token.empty()) return false;
  for (char& c : token)
    if (c == 'D' || c == 'd') c = 'E';
  char* end = nullptr;
  const double value = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size() && !std::isfinite(value);
}

// The real numbers of an IGES file's parameter section are checked before OpenCASCADE reads
// them: on an infinite coordinate its transfer loops, as the STEP transfer did on one. Each
// entity's parameters are the first 64 columns of its P lines run together (a string may
// continue on the next line); strings (nH...) are passed over.
void requireFiniteIgesNumbers(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  std::string global, parameters, entity, line;
  char delimiter = ',', record = ';';
  bool delimitersKnown = false;
  auto check = [&] {
    size_t pos = 0;
    while (pos < parameters.size()) {
      while (pos < parameters.size() && parameters[pos] == ' ') ++pos;
      size_t digits = pos;
      while (digits < parameters.size() && std::isdigit(static_cast<unsigned char>(parameters[digits]))) ++digits;
      if (digits > pos && digits < parameters.size() && parameters[digits] == 'H') {
        pos = digits + 1 + std::min<size_t>(std::stoul(parameters.substr(pos, std::min<size_t>(digits - pos, 9))),
                                            parameters.size());
        while (pos < parameters.size() && parameters[pos] != delimiter && parameters[pos] != record) ++pos;
        ++pos;
        continue;
      }
      const size_t end = parameters.find_first_of(std::string{delimiter, record}, pos);
      std::string token = parameters.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
      token.erase(token.find_last_not_of(' ') + 1);  // leading spaces are skipped above
      if (nonFiniteReal(token))
        throw InputError(what + " has a number that is not finite (" + token.substr(0, 40) +
                         ") in the parameters of IGES entity DE " + entity +
                         ": the file is damaged; export it again from the CAD tool");
      if (end == std::string::npos) break;
      pos = end + 1;
    }
    parameters.clear();
  };
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.size() < 73) continue;
    if (line[72] == 'G') {
      global += line.substr(0, 72);
    } else if (line[72] == 'P') {
      if (!delimitersKnown) {
        std::tie(delimiter, record) = igesDelimiters(global);
        delimitersKnown = true;
      }
      std::string owner = line.substr(64, 8);
      owner.erase(0, owner.find_first_not_of(" 0"));  // the directory entry's number, "0000011" as 11
      if (owner != entity) {
        check();
        entity = owner;
      }
      parameters += line.substr(0, 64);
    }
  }
  check();
}

// The section letter of an IGES line (S, G, D, P, T) as OpenCASCADE's line reader finds it:
// column 73 before a sequence number, else, on a line not to the standard, the last letter
// before the trailing number; 0 for neither.
char igesSection(std::string line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
  if (line.size() > 73) {
    const std::string sequence = line.substr(73);
    const size_t digit = sequence.find_first_not_of(' ');
    if (digit != std::string::npos && std::isdigit(static_cast<unsigned char>(sequence[digit])) &&
        std::string("SGDPT").find(line[72]) != std::string::npos)
      return line[72];
  }
  line.erase(line.find_last_not_of(' ') + 1);
  size_t end = line.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(line[end - 1]))) --end;
  if (end == line.size()) return 0;
  while (end > 0 && line[end - 1] == ' ') --end;
  return end > 0 && std::string("SGDPT").find(line[end - 1]) != std::string::npos ? line[end - 1] : 0;
}

// OpenCASCADE's IGES parser (IGESFile, C with static state) files parameter lines under the
// directory entry last read. In a file whose parameter section comes before any directory entry
// it uses the entry left from the previous IGES file this process read, freed since: a crash
// (a segfault in iges_newparam), or worse. Such a file is damaged anyway.
void requireIgesDirectoryBeforeParameters(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    const char section = igesSection(line);
    if (section == 'D') return;
    if (section == 'P')
      throw InputError(what + " is not a readable IGES file: its parameter data (line " + std::to_string(number) +
                       ") comes before any directory entry (D lines); the file is damaged or cut, export it "
                       "again (IGES 5.3, or better STEP) from the CAD tool");
  }
}

}  // namespace

double declaredStepUncertainty(const std::string& path, const std::string& what) {
  const std::string ext = lowerExtension(path);
  if (ext != "step" && ext != "stp") throw InputError(what + " is no STEP file (.step, .stp)");
  try {
    STEPControl_Reader reader;
    readStepModel(reader, path, what);
    return largestStepUncertainty(reader);
  } catch (const Standard_Failure& failure) {
    throw unreadableFile(what, failure);
  }
}

TopoDS_Shape readShapeFile(const std::string& path, const std::string& what, double* declaredUncertainty) {
  if (declaredUncertainty) *declaredUncertainty = 0;
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
      readStepModel(reader, path, what);
      requireFiniteStepPoints(reader, what);
      if (reader.TransferRoots() == 0)
        throw InputError(what + " holds no shape OpenCASCADE can transfer: export it again as STEP AP203/AP214");
      shape = reader.OneShape();
      if (declaredUncertainty) *declaredUncertainty = largestStepUncertainty(reader);
    } else if (ext == "iges" || ext == "igs") {
      requireFiniteIgesNumbers(path, what);
      requireIgesDirectoryBeforeParameters(path, what);
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
    throw unreadableFile(what, failure);
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
