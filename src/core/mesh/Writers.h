#pragma once
// Mesh files for solvers and viewers. Coordinates are written so that they read back exactly
// (17 significant digits where needed), so nodes put exactly on CAD faces stay there; the one
// exception is noted at writeInp.
// Failures to open or write a file throw oraclemesh::Error naming the path.
#include <string>
#include <vector>

#include "mesh/InterfaceKinds.h"
#include "mesh/Surfaces.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

// VTK XML unstructured grid, ASCII (ParaView, meshio). Cells are VTK_TETRA (10) or
// VTK_QUADRATIC_TETRA (24, node order = TetMesh's: corners, then mid nodes 01,12,20,03,13,23).
// Cell data "material" (Int32); point data "vertex_dimension" (Int32) when the mesh has it.
// Beside it, surfacesVtuPath(path): the interfaces and exteriors (meshSurfaces) as VTK_TRIANGLE
// (5) or VTK_QUADRATIC_TRIANGLE (22) cells over the same points, cell data "surface" (index
// in meshSurfaces' order, each index named in a "<!-- surface i: name -->" line at the top,
// names as the INP's *SURFACE), "material" and "other_material" (0 = exterior); ParaView:
// Threshold on "surface", or on material / other_material for one part's faces.
void writeVtu(const std::string& path, const TetMesh& mesh, const MaterialNames& names = {});
// The same with the surfaces given (meshSurfaces(mesh, plan) taken before an interface split,
// which a split mesh no longer shows as interfaces).
void writeVtu(const std::string& path, const TetMesh& mesh, const MaterialNames& names,
              const std::vector<MeshSurface>& surfaces);

// "<path without its extension>_surfaces.vtu".
std::string surfacesVtuPath(const std::string& vtuPath);

// Abaqus / CalculiX input deck: *NODE (NSET=Nall), then one *ELEMENT block per material with
// ELSET=Material<id>, TYPE=C3D4 or C3D10, and *ELSET Eall naming every element. Node ids are
// point index + 1, element ids are tet index + 1. C3D10 node order is corners 1-4, then mid
// nodes 12, 23, 31, 14, 24, 34, corners with positive volume (what ccx requires).
// Coordinates: CalculiX reads at most 20 characters per coordinate, so a number whose exact
// form is longer (e.g. 3.3333333333333337e-06) is rounded to the most digits that fit, at
// least 14 significant ones (relative error <= 5e-14; 13 digits for |x| < 1e-99 or > 1e99).
// Then one *SURFACE, TYPE=ELEMENT per interface and per part exterior (meshSurfaces), named
// by surfaceNames after the parts in `names`, as "element, S<n>" lines (kCalculixTetFaces).
// After them, for every tied or contact pair of `plan` (interfaceConstraints): a *TIE, or a
// *SURFACE INTERACTION (LINEAR pressure-overclosure, InterfaceConstraint::contact_stiffness; *FRICTION when the pair has a coefficient)
// and a surface-to-surface *CONTACT PAIR, slave surface first. No *STEP: these are model
// definitions, valid before the user's step. Without `surfaces`, meshSurfaces(mesh), all bonded.
void writeInp(const std::string& path, const TetMesh& mesh, const MaterialNames& names = {});
void writeInp(const std::string& path, const TetMesh& mesh, const MaterialNames& names,
              const std::vector<MeshSurface>& surfaces, const InterfacePlan& plan);

// Writes by file extension (case-insensitive): .vtu or .inp. Any other extension throws
// oraclemesh::InputError naming the path and the supported extensions.
void writeMeshFile(const std::string& path, const TetMesh& mesh, const MaterialNames& names = {});
void writeMeshFile(const std::string& path, const TetMesh& mesh, const MaterialNames& names,
                   const std::vector<MeshSurface>& surfaces, const InterfacePlan& plan);
// Why `path` cannot be written as a mesh file (its extension), or "" when it can.
std::string meshFileFormatProblem(const std::string& path);

}  // namespace oraclemesh
