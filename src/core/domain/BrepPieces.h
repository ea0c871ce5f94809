#pragma once
// How many separate pieces of volume a B-rep input may be. A valid OpenCASCADE solid can be
// two volumes that touch only along an edge (presse_asm.step's ram: a tube standing on a rod
// whose rim meets the tube's bore along one circle), and a mesh of it rightly has two pieces.
#include "domain/BrepTopology.h"

namespace oraclemesh {

// An upper bound on the volume pieces of `brep`'s solids: the groups of outer-shell faces
// joined through edges that exactly two faces share. Where pieces touch, the edge is shared by
// more faces or lies on another edge, and joins nothing there; so a piece may count as several
// groups but two pieces never count as one, and a solid with no such edge gives exactly its
// number of pieces (1). Void shells bound no piece of their own.
int volumePiecesAtMost(const BrepTopology& brep);

}  // namespace oraclemesh
