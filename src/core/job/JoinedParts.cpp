#include "job/JoinedParts.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
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

// The fraction of a triangle where a function linear over it, with values d[0..2] at its
// corners, exceeds `level` (all of it when a corner has no part within reach: infinity).
double fractionAbove(std::array<double, 3> d, double level) {
  std::sort(d.begin(), d.end());
  const double low = d[0], mid = d[1], high = d[2];
  if (!std::isfinite(high)) return 1;
  if (level >= high) return 0;
  if (level <= low) return 1;
  if (level <= mid) return 1 - (level - low) * (level - low) / ((mid - low) * (high - low));
  return (high - level) * (high - level) / ((high - low) * (high - mid));
}

}  // namespace

std::vector<JoinedAcrossGap> measureInterfaceGaps(const TetMesh& mesh, const HierarchicalOracle& oracle,
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
    std::array<double, 3> gaps{};
    Point3 at{};
    for (int k = 0; k < 3; ++k) {
      const int64_t v = t.v[k];
      const double kept = static_cast<size_t>(v) < distanceKeptOffCad.size() ? distanceKeptOffCad[v] : 0.0;
      const double d = std::max(distanceTo(mesh.points[v], v, a), distanceTo(mesh.points[v], v, b)) - kept;
      gaps[k] = d;
      const double allowed = bondedWedges ? std::max(tolerance, bondedWedges->widthAt(mesh.points[v])) : tolerance;
      beyondAllowed = std::min(beyondAllowed, d - allowed);
      if (d < faceGap) {
        faceGap = d;
        at = mesh.points[v];
      }
    }
    pair.beyond_contact_area += area * fractionAbove(gaps, tolerance);
    if (beyondAllowed <= 0) continue;
    pair.joined_area += area;
    if (faceGap > pair.widest_gap) {
      pair.widest_gap = faceGap;
      pair.widest_at = at;
    }
  }
  std::vector<JoinedAcrossGap> measured;
  for (const auto& [key, pair] : pairs) measured.push_back(pair);
  return measured;
}

std::vector<JoinedAcrossGap> joinedPairs(const std::vector<JoinedAcrossGap>& measured) {
  std::vector<JoinedAcrossGap> joined;
  std::copy_if(measured.begin(), measured.end(), std::back_inserter(joined),
               [](const JoinedAcrossGap& j) { return j.joined_area > 0; });
  return joined;
}

std::vector<JoinedAcrossGap> findPartsJoinedAcrossGaps(const TetMesh& mesh, const HierarchicalOracle& oracle,
                                                       double tolerance, const std::vector<double>& distanceKeptOffCad,
                                                       const BondedWedges* bondedWedges) {
  return joinedPairs(measureInterfaceGaps(mesh, oracle, tolerance, distanceKeptOffCad, bondedWedges));
}

}  // namespace oraclemesh
