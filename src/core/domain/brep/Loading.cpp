// BrepSolid's loaders: the solids of a file or BREP text as oracle inputs, one per solid or
// all together, with warnings for the open shells left out.
#include "domain/BrepSolid.h"

#include <Precision.hxx>
#include <Standard_Failure.hxx>

#include <cstdio>

#include "Error.h"
#include "domain/brep/ShapeFiles.h"
#include "domain/brep/SolidChecks.h"

namespace oraclemesh {

namespace {

std::string describe(const std::string& name, const std::string& path) {
  return "input '" + name + "'" + (path.empty() ? "" : " (file '" + path + "')");
}

// Errors of the constructor name the input; loaders of files name the file as well, since a
// user may have several inputs with similar names.
template <class Action>
auto namingTheFile(const std::string& name, const std::string& what, Action action) {
  try {
    return action();
  } catch (const InputError& e) {
    std::string message = e.what();
    const std::string prefix = "input '" + name + "'";
    if (message.rfind(prefix, 0) == 0 && what != prefix) message = what + message.substr(prefix.size());
    throw InputError(message);
  }
}

// OpenCASCADE's tolerances are absolute (Precision::Confusion() = 1e-7): a model only a few
// of them across fails in its mesher with "invalid parameter value", which names neither
// the model nor the cause (wrong units, usually m for mm).
void checkModelSize(const TopoDS_Shape& shape, const std::string& what) {
  const Bbox box = boxOf(shape);
  if (box.empty()) return;  // no geometry: the solid checks say so
  const double diagonal = box.diagonal();
  const double smallest = 1000 * Precision::Confusion();
  if (diagonal < smallest) {
    char text[240];
    std::snprintf(text, sizeof text,
                  " is only %g model units across, too small to mesh (OpenCASCADE's tolerance is %g): check the "
                  "units (FreeCAD works in mm) or scale the model up to at least %g",
                  diagonal, Precision::Confusion(), smallest);
    throw InputError(what + text);
  }
}

}  // namespace

static TopoDS_Shape readSolidBrepText(const std::string& text, const std::string& name) {
  return readBrepText(text, "input '" + name + "' (BREP text)", ": pass Shape.exportBrepToString() of a solid");
}

BrepSolid::Loaded BrepSolid::load(const TopoDS_Shape& shape, const std::string& name, Grouping grouping,
                                  const std::string& path, Tessellation tessellation) {
  const std::string what = describe(name, path);
  Loaded loaded;
  SolidPieces pieces;
  try {
    checkModelSize(shape, what);
    pieces = solidPieces(shape, what);
  } catch (const Standard_Failure& failure) {
    throw InputError(what + " could not be processed by OpenCASCADE (" + failure.GetMessageString() +
                     "): check it with Part > Check geometry and repair it");
  }
  for (const std::string& s : pieces.skipped)
    loaded.warnings.push_back(what + ": " + s + " bounds no volume and was left out; close it (Part > Shape builder) "
                              "if it should be meshed");
  // The constructor taking the checked pieces is private (make_shared cannot reach it).
  if (grouping == Grouping::Together || pieces.solids.size() == 1) {
    loaded.solids.push_back(namingTheFile(name, what, [&] {
      return std::shared_ptr<BrepSolid>(new BrepSolid(validatedPart(pieces, 0, pieces.solids.size()), name, tessellation));
    }));
    return loaded;
  }
  for (size_t i = 0; i < pieces.solids.size(); ++i) {
    const std::string solidName = name + "#" + std::to_string(i + 1);
    loaded.solids.push_back(namingTheFile(solidName, describe(solidName, path), [&] {
      return std::shared_ptr<BrepSolid>(new BrepSolid(validatedPart(pieces, i, i + 1), solidName, tessellation));
    }));
  }
  return loaded;
}

BrepSolid::Loaded BrepSolid::loadFile(const std::string& path, const std::string& name, Grouping grouping) {
  double uncertainty = 0;
  const TopoDS_Shape shape = readShapeFile(path, describe(name, path), &uncertainty);
  Loaded loaded = load(shape, name, grouping, path);
  loaded.declared_uncertainty = uncertainty;
  return loaded;
}

BrepSolid::Loaded BrepSolid::loadBrepText(const std::string& text, const std::string& name, Grouping grouping) {
  return load(readSolidBrepText(text, name), name, grouping);
}

std::shared_ptr<BrepSolid> BrepSolid::fromFile(const std::string& path, const std::string& name) {
  const std::string what = describe(name, path);
  const TopoDS_Shape shape = readShapeFile(path, what);
  return namingTheFile(name, what, [&] { return std::make_shared<BrepSolid>(shape, name); });
}

std::shared_ptr<BrepSolid> BrepSolid::fromBrepText(const std::string& text, const std::string& name) {
  return std::make_shared<BrepSolid>(readSolidBrepText(text, name), name);
}

}  // namespace oraclemesh
