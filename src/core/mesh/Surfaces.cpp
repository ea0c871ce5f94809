#include "mesh/Surfaces.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include "mesh/Topology.h"

namespace oraclemesh {

namespace {

// CalculiX label (0..3 = S1..S4) of the face opposite each corner: S1 = 1-2-3 is opposite
// corner 4, S2 = 1-4-2 opposite 3, S3 = 2-4-3 opposite 1, S4 = 3-4-1 opposite 2.
constexpr int kLabelOfFaceOpposite[4] = {2, 3, 1, 0};

double triangleArea(const TetMesh& mesh, const ElementFace& f) {
  const auto& tet = mesh.tets[f.tet];
  const Point3& a = mesh.points[tet[kCalculixTetFaces[f.face][0]]];
  const Point3& b = mesh.points[tet[kCalculixTetFaces[f.face][1]]];
  const Point3& c = mesh.points[tet[kCalculixTetFaces[f.face][2]]];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

}  // namespace

std::vector<MeshSurface> meshSurfaces(const TetMesh& mesh, const InterfacePlan& plan) {
  // The boundary as extractBoundary sees it: an interface's faces come from the smaller
  // material's tet, faces shared by more than two tets are left out (checkConformity counts them).
  std::map<std::pair<int, int>, MeshSurface> byPair;
  for (const BoundaryFace& face : boundaryElementFaces(mesh)) {
    const int material = mesh.tet_materials[face.tet];
    MeshSurface& s = byPair[{material, face.material_out}];
    s.material = material;
    s.other_material = face.material_out;
    s.faces.push_back({face.tet, kLabelOfFaceOpposite[face.opposite_corner]});
    if (face.material_out == 0 || plan.bonded(material, face.material_out)) continue;
    MeshSurface& back = byPair[{face.material_out, material}];
    back.material = face.material_out;
    back.other_material = material;
    back.faces.push_back({face.other_tet, kLabelOfFaceOpposite[face.other_opposite_corner]});
  }
  std::vector<MeshSurface> result;
  for (auto& [pair, s] : byPair) {
    // By element, as solvers list them.
    std::sort(s.faces.begin(), s.faces.end(),
              [](const ElementFace& x, const ElementFace& y) { return x.tet != y.tet ? x.tet < y.tet : x.face < y.face; });
    for (const ElementFace& f : s.faces) s.area += triangleArea(mesh, f);
    result.push_back(std::move(s));
  }
  return result;
}

std::string materialName(const MaterialNames& names, int material) {
  const auto it = names.find(material);
  return it != names.end() ? it->second : "Material" + std::to_string(material);
}

std::string inpName(const std::string& text) {
  std::string name;
  for (unsigned char c : text) name += std::isalnum(c) && c < 128 ? static_cast<char>(c) : '_';
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) name = "S" + name;
  return name.substr(0, kMaxInpNameLength);
}

std::string surfaceName(const MaterialNames& names, const MeshSurface& surface) {
  if (surface.other_material == 0) return inpName("Exterior_" + materialName(names, surface.material));
  return inpName("Interface_" + materialName(names, surface.material) + "_" +
                 materialName(names, surface.other_material));
}

std::vector<std::string> surfaceNames(const MaterialNames& names, const std::vector<MeshSurface>& surfaces) {
  std::vector<std::string> result;
  std::set<std::string> taken;  // upper case, as CalculiX compares names
  auto upper = [](std::string text) {
    for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return text;
  };
  for (const MeshSurface& surface : surfaces) {
    const std::string base = surfaceName(names, surface);
    std::string name = base;
    for (int k = 2; !taken.insert(upper(name)).second; ++k) {
      const std::string suffix = "_" + std::to_string(k);
      name = base.substr(0, kMaxInpNameLength - suffix.size()) + suffix;
    }
    result.push_back(name);
  }
  return result;
}

}  // namespace oraclemesh
