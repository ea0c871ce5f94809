#pragma once
// The named surfaces of a mesh: every interface between two materials (parts) and the
// exterior of each material, as element faces. Solvers and FEM pre-processors refer to
// surfaces by (element, face) pairs, so this is what the INP, the report and FreeCAD get.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/InterfaceKinds.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

// Local faces of a tet in CalculiX's (and Abaqus') numbering for C3D4 and C3D10:
// S1 = corners 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1 (zero-based below). For a tet of
// positive volume each triple's right-hand normal points into the element (to the opposite
// corner); CalculiX takes the outward normal from the label, not from this order.
inline constexpr std::array<std::array<int, 3>, 4> kCalculixTetFaces = {{{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}}};

struct ElementFace {
  int64_t tet = 0;  // index into TetMesh::tets
  int face = 0;     // 0..3 = CalculiX S1..S4
};

struct MeshSurface {
  // The side the faces are taken from: the smaller id of an interface, or the larger for the
  // second side of a pair that is not bonded (whose faces are the same triangles, from that
  // part's tets).
  int material = 0;
  int other_material = 0;  // 0 = the outside: the exterior surface of `material`
  std::vector<ElementFace> faces;  // ordered by tet, then face
  double area = 0;                 // of the flat corner triangles
};

// Interfaces (material < other_material) and exteriors (other_material = 0) of `mesh`,
// sorted by (material, other_material), one per pair that shares at least one face. For every
// pair that `plan` does not bond, also the same faces seen from the larger material's tets
// (material > other_material): a tie or contact needs each part's own faces, and after the
// interface split (mesh/InterfaceSplit) the two parts no longer share them, so call this on
// the mesh before the split (the split keeps tet indices, so the faces stay valid).
std::vector<MeshSurface> meshSurfaces(const TetMesh& mesh, const InterfacePlan& plan = {});

// Names of the parts per material id; a material missing from `names` is "Material<id>".
using MaterialNames = std::map<int, std::string>;

std::string materialName(const MaterialNames& names, int material);

inline constexpr size_t kMaxInpNameLength = 80;  // CalculiX' limit

// A name solvers accept: letters, digits and '_' only (every other character becomes '_'),
// starting with a letter, at most kMaxInpNameLength characters.
std::string inpName(const std::string& text);

// "Interface_<part>_<part>" (material's part first) or "Exterior_<part>", in inpName's alphabet.
std::string surfaceName(const MaterialNames& names, const MeshSurface& surface);

// surfaceName of each surface, made unique: two parts can clean to the same name ("Bolt 1"
// and "Bolt_1", or names cut at 80 characters), and CalculiX reads names without regard to
// case, so a name already given (in any case) gets "_2", "_3", ... in the order of `surfaces`.
// Every writer and the report use these, so a surface has one name everywhere.
std::vector<std::string> surfaceNames(const MaterialNames& names, const std::vector<MeshSurface>& surfaces);

}  // namespace oraclemesh
