#pragma once
// Checks on the loaded inputs, before any size is resolved or any engine runs, for mistakes
// whose symptom downstream would name the wrong cause.
#include "domain/HierarchicalOracle.h"

namespace oraclemesh {

// InputError naming the cut when the cuts remove every material input: the engines would
// only report an empty mesh ("the inputs may be smaller than the sizes").
void checkCutsLeaveMaterial(const HierarchicalOracle& oracle);

}  // namespace oraclemesh
