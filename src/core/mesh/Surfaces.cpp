#include "mesh/Surfaces.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_map>

#include "mesh/Topology.h"

namespace oraclemesh {

namespace {

struct FaceKey {
  std::array<int64_t, 3> v;
  bool operator==(const FaceKey& o) const { return v == o.v; }
};

struct FaceKeyHash {
  size_t operator()(const FaceKey& k) const {
    uint64_t h = 1469598103934665603ull;
    for (int64_t x : k.v) h = (h ^ static_cast<uint64_t>(x)) * 1099511628211ull;
    return static_cast<size_t>(h);
  }
};

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

std::vector<MeshSurface> meshSurfaces(const TetMesh& mesh) {
  requireConsistentIndices(mesh);
  // Up to two (tet, face) per sorted corner triple; a third one makes the face invalid
  // (checkConformity counts it) and it is left out, as extractBoundary does.
  struct Sides {
    ElementFace first, second;
    int count = 0;
  };
  std::unordered_map<FaceKey, Sides, FaceKeyHash> faces;
  faces.reserve(mesh.tets.size() * 2 + 16);
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      FaceKey key;
      for (int i = 0; i < 3; ++i) key.v[i] = mesh.tets[t][kCalculixTetFaces[f][i]];
      std::sort(key.v.begin(), key.v.end());
      Sides& s = faces[key];
      (s.count == 0 ? s.first : s.second) = {static_cast<int64_t>(t), f};
      ++s.count;
    }

  std::map<std::pair<int, int>, MeshSurface> byPair;
  auto add = [&](const ElementFace& face, int other) {
    const int material = mesh.tet_materials[face.tet];
    MeshSurface& s = byPair[{material, other}];
    s.material = material;
    s.other_material = other;
    s.faces.push_back(face);
  };
  for (const auto& [key, s] : faces) {
    if (s.count == 1) {
      add(s.first, 0);
    } else if (s.count == 2) {
      const int a = mesh.tet_materials[s.first.tet], b = mesh.tet_materials[s.second.tet];
      if (a == b) continue;
      // Taken from the smaller material's tet, as extractBoundary orients interfaces.
      if (a < b) add(s.first, b);
      else add(s.second, a);
    }
  }
  std::vector<MeshSurface> result;
  for (auto& [pair, s] : byPair) {
    // The hash map's order is not deterministic; files and reports must be.
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
  return name.substr(0, 80);
}

std::string surfaceName(const MaterialNames& names, const MeshSurface& surface) {
  if (surface.other_material == 0) return inpName("Exterior_" + materialName(names, surface.material));
  return inpName("Interface_" + materialName(names, surface.material) + "_" +
                 materialName(names, surface.other_material));
}

}  // namespace oraclemesh
