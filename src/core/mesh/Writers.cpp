#include "mesh/Writers.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <vector>

#include "Error.h"
#include "mesh/InterfaceConstraints.h"
#include "mesh/Topology.h"

namespace oraclemesh {

namespace {

// A C stdio file (fast formatted output of millions of numbers) that closes itself and turns
// every failure into an Error naming the path.
class OutputFile {
 public:
  explicit OutputFile(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "w")) {
    if (!file_)
      throw Error("cannot write the mesh file '" + path + "': " + std::strerror(errno) +
                  "; check that the folder exists and is writable (output.files)");
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile() {
    if (file_) std::fclose(file_);
  }

  template <typename... Args>
  void print(const char* format, Args... args) {
    std::fprintf(file_, format, args...);
  }
  void print(const char* text) { std::fputs(text, file_); }

  // Flushes and closes; a full disk shows up here rather than being lost in a destructor.
  void close() {
    const bool failed = std::ferror(file_) != 0;
    const int closeResult = std::fclose(file_);
    file_ = nullptr;
    if (failed || closeResult != 0)
      throw Error("writing the mesh file '" + path_ + "' failed (disk full or file system error?)");
  }

 private:
  std::string path_;
  std::FILE* file_;
};

constexpr int kVtkTetra = 10;
constexpr int kVtkQuadraticTetra = 24;
constexpr int kVtkTriangle = 5;
constexpr int kVtkQuadraticTriangle = 22;

// CalculiX reads each *NODE coordinate from the first 20 characters of its field (Fortran
// format f20.0) and stops with "*ERROR reading *NODE" on a longer one, such as %.17g of
// 3.3333333333333337e-06. So: the shortest of %.15g..%.17g that reads back exactly, if it
// fits in 20 characters; otherwise the most digits that fit: at least 14 significant digits
// (relative rounding <= 5e-14) for two-digit exponents, 13 for three-digit ones, far below
// the 1e-9 to which boundary nodes are placed on the CAD faces.
constexpr int kCalculixNumberWidth = 20;

std::string inpCoordinate(double x) {
  char text[64];
  for (int digits = 15; digits <= 17; ++digits) {
    const int length = std::snprintf(text, sizeof text, "%.*g", digits, x);
    if (std::strtod(text, nullptr) == x) {
      if (length <= kCalculixNumberWidth) return text;
      break;
    }
  }
  // Ends at the latest with 13 digits: "-1.234567890123e-300" has 20 characters.
  for (int digits = 17;; --digits)
    if (std::snprintf(text, sizeof text, "%.*g", digits, x) <= kCalculixNumberWidth) return text;
}

std::string lowerCaseExtension(const std::string& path) {
  const size_t slash = path.find_last_of("/\\");
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// Node indices of tet t in the node order shared by VTK's quadratic tetra and Abaqus' C3D10
// (corners, then mid nodes 01, 12, 20, 03, 13, 23 = 12, 23, 31, 14, 24, 34 one-based), which
// is also TetMesh's.
struct ElementNodes {
  std::array<int64_t, 10> index{};
  int count = 0;
};

ElementNodes elementNodes(const TetMesh& mesh, size_t t) {
  ElementNodes nodes;
  for (int64_t v : mesh.tets[t]) nodes.index[nodes.count++] = v;
  if (mesh.order() == 2)
    for (int64_t v : mesh.tet_mid_nodes[t]) nodes.index[nodes.count++] = v;
  return nodes;
}

// NaN or infinite coordinates would make a file that every reader rejects or misreads.
void requireFinitePoints(const TetMesh& mesh, const std::string& path) {
  for (size_t i = 0; i < mesh.points.size(); ++i)
    for (double c : mesh.points[i])
      if (!std::isfinite(c))
        throw Error("internal error: point " + std::to_string(i) + " of the mesh for '" + path +
                    "' has a non-finite coordinate; please report this with the job file");
}

}  // namespace

std::string surfacesVtuPath(const std::string& vtuPath) {
  return vtuPath.substr(0, vtuPath.size() - lowerCaseExtension(vtuPath).size()) + "_surfaces.vtu";
}

namespace {

// The points of a VTU piece; both VTU files share them.
void printVtuPoints(OutputFile& out, const TetMesh& mesh) {
  out.print("      <Points>\n");
  out.print("        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (const Point3& p : mesh.points) out.print("%.17g %.17g %.17g\n", p[0], p[1], p[2]);
  out.print("        </DataArray>\n");
  out.print("      </Points>\n");
}

// After the connectivity: offsets and types of `cells` cells of one type, and the file's end.
void printVtuCellsEnd(OutputFile& out, size_t cells, int nodesPerCell, int cellType) {
  out.print("        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for (size_t i = 1; i <= cells; ++i) out.print("%lld\n", static_cast<long long>(i * nodesPerCell));
  out.print("        </DataArray>\n");
  out.print("        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for (size_t i = 0; i < cells; ++i) out.print("%d\n", cellType);
  out.print("        </DataArray>\n");
  out.print("      </Cells>\n");
  out.print("    </Piece>\n");
  out.print("  </UnstructuredGrid>\n");
  out.print("</VTKFile>\n");
}

// The interfaces and exteriors as triangles (quadratic for tet10) over the same points as the
// volume file: ParaView shows faces only as cells of their own, and a file of its own keeps
// the volume file's cells the tets alone (what meshio users and the tests read).

void writeSurfacesVtu(const std::string& path, const TetMesh& mesh, const MaterialNames& names,
                      const std::vector<MeshSurface>& surfaces) {
  // Mid-node column of TetMesh::tet_mid_nodes for the edge between two corners.
  auto midColumn = [](int a, int b) {
    static constexpr int kColumn[4][4] = {{-1, 0, 2, 3}, {0, -1, 1, 4}, {2, 1, -1, 5}, {3, 4, 5, -1}};
    return kColumn[a][b];
  };
  const int nodesPerCell = mesh.order() == 2 ? 6 : 3;
  size_t cells = 0;
  for (const MeshSurface& s : surfaces) cells += s.faces.size();
  OutputFile out(path);
  out.print("<?xml version=\"1.0\"?>\n");
  out.print("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
  out.print("  <UnstructuredGrid>\n");
  // The names as a comment, not a VTK string array: meshio (and so many users' scripts) reject
  // String arrays, and the index in "surface" is all ParaView needs to select one.
  const std::vector<std::string> surfaceNamesInOrder = surfaceNames(names, surfaces);
  for (size_t i = 0; i < surfaces.size(); ++i)
    out.print("  <!-- surface %zu: %s -->\n", i, surfaceNamesInOrder[i].c_str());
  out.print("    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n", mesh.points.size(), cells);
  out.print("      <CellData>\n");
  const char* arrays[3] = {"surface", "material", "other_material"};
  for (int a = 0; a < 3; ++a) {
    out.print("        <DataArray type=\"Int32\" Name=\"%s\" format=\"ascii\">\n", arrays[a]);
    for (size_t i = 0; i < surfaces.size(); ++i) {
      const int value = a == 0 ? static_cast<int>(i) : a == 1 ? surfaces[i].material : surfaces[i].other_material;
      for (size_t k = 0; k < surfaces[i].faces.size(); ++k) out.print("%d\n", value);
    }
    out.print("        </DataArray>\n");
  }
  out.print("      </CellData>\n");
  printVtuPoints(out, mesh);
  out.print("      <Cells>\n");
  out.print("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for (const MeshSurface& s : surfaces)
    for (const ElementFace& f : s.faces) {
      const std::array<int, 3>& c = kCalculixTetFaces[f.face];
      const auto& tet = mesh.tets[f.tet];
      out.print("%lld %lld %lld", static_cast<long long>(tet[c[0]]), static_cast<long long>(tet[c[1]]),
                static_cast<long long>(tet[c[2]]));
      if (mesh.order() == 2)
        for (int e = 0; e < 3; ++e)
          out.print(" %lld", static_cast<long long>(mesh.tet_mid_nodes[f.tet][midColumn(c[e], c[(e + 1) % 3])]));
      out.print("\n");
    }
  out.print("        </DataArray>\n");
  printVtuCellsEnd(out, cells, nodesPerCell, mesh.order() == 2 ? kVtkQuadraticTriangle : kVtkTriangle);
  out.close();
}

void writeTetsVtu(const std::string& path, const TetMesh& mesh) {
  requireConsistentIndices(mesh);
  requireFinitePoints(mesh, path);
  const int nodesPerCell = mesh.order() == 2 ? 10 : 4;
  const int cellType = mesh.order() == 2 ? kVtkQuadraticTetra : kVtkTetra;
  OutputFile out(path);
  out.print("<?xml version=\"1.0\"?>\n");
  out.print("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
  out.print("  <UnstructuredGrid>\n");
  out.print("    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n", mesh.points.size(), mesh.tets.size());

  if (mesh.vertex_dimension.size() == mesh.points.size() && !mesh.points.empty()) {
    out.print("      <PointData>\n");
    out.print("        <DataArray type=\"Int32\" Name=\"vertex_dimension\" format=\"ascii\">\n");
    for (int d : mesh.vertex_dimension) out.print("%d\n", d);
    out.print("        </DataArray>\n");
    out.print("      </PointData>\n");
  }
  out.print("      <CellData>\n");
  out.print("        <DataArray type=\"Int32\" Name=\"material\" format=\"ascii\">\n");
  for (int m : mesh.tet_materials) out.print("%d\n", m);
  out.print("        </DataArray>\n");
  out.print("      </CellData>\n");

  printVtuPoints(out, mesh);

  out.print("      <Cells>\n");
  out.print("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const ElementNodes nodes = elementNodes(mesh, t);
    for (int i = 0; i < nodes.count; ++i)
      out.print(i + 1 < nodes.count ? "%lld " : "%lld\n", static_cast<long long>(nodes.index[i]));
  }
  out.print("        </DataArray>\n");
  printVtuCellsEnd(out, mesh.tets.size(), nodesPerCell, cellType);
  out.close();
}

}  // namespace

void writeVtu(const std::string& path, const TetMesh& mesh, const MaterialNames& names) {
  writeVtu(path, mesh, names, meshSurfaces(mesh));
}

void writeVtu(const std::string& path, const TetMesh& mesh, const MaterialNames& names,
              const std::vector<MeshSurface>& surfaces) {
  writeTetsVtu(path, mesh);
  writeSurfacesVtu(surfacesVtuPath(path), mesh, names, surfaces);
}

void writeInp(const std::string& path, const TetMesh& mesh, const MaterialNames& names) {
  writeInp(path, mesh, names, meshSurfaces(mesh), InterfacePlan());
}

void writeInp(const std::string& path, const TetMesh& mesh, const MaterialNames& names,
              const std::vector<MeshSurface>& surfaces, const InterfacePlan& plan) {
  requireConsistentIndices(mesh);
  requireFinitePoints(mesh, path);
  const char* elementType = mesh.order() == 2 ? "C3D10" : "C3D4";
  OutputFile out(path);
  out.print("** OracleMesh tetrahedral mesh: %zu nodes, %zu %s elements\n", mesh.points.size(), mesh.tets.size(),
            elementType);
  out.print("** element sets Material<id> (one per material) and Eall (all elements); surfaces Interface_<part>_<part>\n");
  out.print("** and Exterior_<part> over element faces; where two parts are not bonded (tied, contact, separate)\n");
  out.print("** they have their own nodes there and both sides are surfaces: Interface_<a>_<b> from a's faces and\n");
  out.print("** Interface_<b>_<a> from b's; *TIE and *CONTACT PAIR cards at the end join tied and contact pairs\n");
  out.print("*NODE, NSET=Nall\n");
  for (size_t i = 0; i < mesh.points.size(); ++i)
    out.print("%zu, %s, %s, %s\n", i + 1, inpCoordinate(mesh.points[i][0]).c_str(),
              inpCoordinate(mesh.points[i][1]).c_str(), inpCoordinate(mesh.points[i][2]).c_str());

  // Element ids stay tet index + 1, so a result on element k maps back to tets[k - 1].
  std::map<int, std::vector<size_t>> tetsOfMaterial;
  for (size_t t = 0; t < mesh.tets.size(); ++t) tetsOfMaterial[mesh.tet_materials[t]].push_back(t);
  for (const auto& [material, tets] : tetsOfMaterial) {
    out.print("*ELEMENT, TYPE=%s, ELSET=Material%d\n", elementType, material);
    for (size_t t : tets) {
      out.print("%zu", t + 1);
      const ElementNodes nodes = elementNodes(mesh, t);
      for (int i = 0; i < nodes.count; ++i) out.print(", %lld", static_cast<long long>(nodes.index[i] + 1));
      out.print("\n");
    }
  }
  if (!tetsOfMaterial.empty()) {
    out.print("*ELSET, ELSET=Eall\n");
    for (const auto& [material, tets] : tetsOfMaterial) out.print("Material%d\n", material);
  }
  // Loads, ties and contacts in CalculiX refer to element faces; these give users and the
  // workbench every interface and exterior by the parts' names.
  const std::vector<std::string> surfaceNamesInOrder = surfaceNames(names, surfaces);
  for (size_t i = 0; i < surfaces.size(); ++i) {
    out.print("*SURFACE, NAME=%s, TYPE=ELEMENT\n", surfaceNamesInOrder[i].c_str());
    for (const ElementFace& f : surfaces[i].faces)
      out.print("%lld, S%d\n", static_cast<long long>(f.tet + 1), f.face + 1);
  }
  out.print(calculixInterfaceCards(interfaceConstraints(mesh, surfaces, names, plan)).c_str());
  out.close();
}

std::string meshFileFormatProblem(const std::string& path) {
  const std::string ext = lowerCaseExtension(path);
  if (ext == ".vtu" || ext == ".inp") return "";
  return (ext.empty() ? "it has no file extension" : "unknown extension '" + ext + "'") +
         "; supported mesh file extensions are .vtu (VTK, ParaView) and .inp (Abaqus / CalculiX)";
}

void writeMeshFile(const std::string& path, const TetMesh& mesh, const MaterialNames& names) {
  writeMeshFile(path, mesh, names, meshSurfaces(mesh), InterfacePlan());
}

void writeMeshFile(const std::string& path, const TetMesh& mesh, const MaterialNames& names,
                   const std::vector<MeshSurface>& surfaces, const InterfacePlan& plan) {
  const std::string ext = lowerCaseExtension(path);
  if (ext == ".vtu") return writeVtu(path, mesh, names, surfaces);
  if (ext == ".inp") return writeInp(path, mesh, names, surfaces, plan);
  throw InputError("cannot write the mesh file '" + path + "': " + meshFileFormatProblem(path));
}

}  // namespace oraclemesh
