#pragma once
// The 2-3 flip: the face shared by two tets of one material becomes the edge between their
// apexes, with three tets around it.
#include <cstdint>

#include "improve/ImprovementMesh.h"

namespace oraclemesh {

// Flips face abc when it has two tets of one material, is no boundary or interface triangle,
// the new edge pierces it (all three new tets positive by the exact predicate), their smallest
// dihedral angle beats that of the two old tets and none is bigger than the worst old one.
bool removeFace(ImprovementMesh& mesh, int64_t a, int64_t b, int64_t c);

}  // namespace oraclemesh
