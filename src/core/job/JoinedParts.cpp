#include "job/JoinedParts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>
#include <utility>

namespace oraclemesh {

namespace {

double triangleArea(const Point3& a, const Point3& b, const Point3& c) { return 0.5 * norm(cross(b - a, c - a)); }

// Distances from mesh vertices to the closure of one material's inputs, each computed once
// (a vertex is shared by several faces): 0 inside an input, else the distance to the nearest
// input boundary within reach (infinity when no input's box comes within `reach`).
class MaterialDistances {
 public:
  MaterialDistances(const HierarchicalOracle& oracle, double reach) : oracle_(oracle), reach_(reach) {}

  double operator()(const Point3& p, int64_t vertex, int material) {
    const auto [it, added] = cache_.emplace(std::make_pair(vertex, material), 0.0);
    if (!added) return it->second;
    return it->second = oracle_.distanceToMaterial(p, material, reach_);
  }

 private:
  struct PairHash {
    size_t operator()(const std::pair<int64_t, int>& k) const {
      return std::hash<int64_t>()(k.first * 1000003 + k.second);
    }
  };
  const HierarchicalOracle& oracle_;
  double reach_;
  std::unordered_map<std::pair<int64_t, int>, double, PairHash> cache_;
};

}  // namespace

std::vector<JoinedAcrossGap> findPartsJoinedAcrossGaps(const TetMesh& mesh, const HierarchicalOracle& oracle,
                                                       double tolerance, const std::vector<double>& distanceKeptOffCad,
                                                       const BondedWedges* bondedWedges) {
  // A gap wider than the model is no gap of two parts; the reach only bounds the projections.
  MaterialDistances distanceTo(oracle, oracle.diagonal());
  std::map<std::pair<int, int>, JoinedAcrossGap> pairs;
  for (const BoundaryTriangle& t : mesh.boundary) {
    if (t.material_in <= 0 || t.material_out <= 0 || t.material_in == t.material_out) continue;
    const int a = std::min(t.material_in, t.material_out), b = std::max(t.material_in, t.material_out);
    JoinedAcrossGap& pair = pairs[{a, b}];
    pair.material = a;
    pair.other_material = b;
    const double area = triangleArea(mesh.points[t.v[0]], mesh.points[t.v[1]], mesh.points[t.v[2]]);
    pair.interface_area += area;
    // Across a gap no node of the face is on both parts. Where the parts do touch, a face at
    // the edge of their contact may have one or two nodes off it (the mesh's interface edge is
    // a chord away from the CAD's) and still one on it.
    double faceGap = std::numeric_limits<double>::infinity();
    double beyondAllowed = std::numeric_limits<double>::infinity();  // the least over the face's nodes
    Point3 at{};
    for (int64_t v : t.v) {
      const double kept = static_cast<size_t>(v) < distanceKeptOffCad.size() ? distanceKeptOffCad[v] : 0.0;
      const double d = std::max(distanceTo(mesh.points[v], v, a), distanceTo(mesh.points[v], v, b)) - kept;
      const double allowed = bondedWedges ? std::max(tolerance, bondedWedges->widthAt(mesh.points[v])) : tolerance;
      beyondAllowed = std::min(beyondAllowed, d - allowed);
      if (d < faceGap) {
        faceGap = d;
        at = mesh.points[v];
      }
    }
    if (beyondAllowed <= 0) continue;
    pair.joined_area += area;
    if (faceGap > pair.widest_gap) {
      pair.widest_gap = faceGap;
      pair.widest_at = at;
    }
  }
  std::vector<JoinedAcrossGap> joined;
  for (const auto& [key, pair] : pairs)
    if (pair.joined_area > 0) joined.push_back(pair);
  return joined;
}

}  // namespace oraclemesh
