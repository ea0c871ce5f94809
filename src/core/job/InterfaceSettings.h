#pragma once
// The job's "interfaces" applied to the loaded model: part names to material ids, and what the
// finished mesh says about pairs the job names.
#include <string>
#include <vector>

#include "job/JobSpec.h"
#include "mesh/InterfaceKinds.h"
#include "mesh/InterfaceSplit.h"
#include "mesh/Surfaces.h"

namespace oraclemesh {

// Throws InputError naming interfaces.pairs[i].between[k] (with the known part names) for a
// name that is no part of the model.
InterfacePlan resolveInterfaces(const InterfacesSpec& spec, const MaterialNames& names);

// Warnings for pairs of the job that share no face in the mesh (the setting changes nothing
// there, or only where they meet along an edge or at a point).
std::vector<std::string> interfaceWarnings(const InterfacePlan& plan, const std::vector<MeshSurface>& surfaces,
                                           const MaterialNames& names);

// Warnings for pairs that are not bonded but stay joined at nodes they share with a part
// bonded to both (InterfaceSplitStats::kept_joined), naming the pair, the count and the parts.
std::vector<std::string> keptJoinedWarnings(const InterfacePlan& plan, const InterfaceSplitStats& split,
                                            const MaterialNames& names);

}  // namespace oraclemesh
