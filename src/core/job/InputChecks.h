#pragma once
// Checks on the loaded inputs, before any size is resolved or any engine runs, for mistakes
// whose symptom downstream would name the wrong cause.
#include <string>

#include "domain/HierarchicalOracle.h"
#include "job/JobSpec.h"

namespace oraclemesh {

// InputError naming the cut when the cuts remove every material input: the engines would
// only report an empty mesh ("the inputs may be smaller than the sizes").
void checkCutsLeaveMaterial(const HierarchicalOracle& oracle);

// For an engine that made no tetrahedron: each material input with its file and how much of
// its box it encloses, and the fix for an input whose CAD is invalid (OpenCASCADE then gives
// it a fraction of its true volume, or none: a STEP file with damaged entities).
std::string whatTheInputsEnclose(const JobSpec& job, const HierarchicalOracle& oracle);

}  // namespace oraclemesh
