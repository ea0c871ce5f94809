#include "improve/FlatCaps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "improve/EdgeRemoval.h"
#include "improve/ImprovementMesh.h"
#include "mesh/Quality.h"
#include "mesh/Topology.h"

namespace oraclemesh {
namespace {

// A sweep over the tets finds caps a previous removal exposed; a handful covers the stacks
// of caps seen on real parts, and a sweep that changes nothing ends the loop.
constexpr int kMaxSweeps = 4;

// Relative room in the size bound of an interface flip.
constexpr double kSizeSlack = 1e-6;

enum class FaceSide { Inner, Outer, Interface };

struct FaceNeighbour {
  FaceSide side = FaceSide::Inner;
  int other_material = 0;  // Interface: the material across
};

FaceNeighbour neighbourAcross(const ImprovementMesh& mesh, int64_t t, int64_t a, int64_t b, int64_t c) {
  const std::vector<int64_t> tets = mesh.tetsWithFace(a, b, c);
  if (tets.size() == 1) return {FaceSide::Outer, 0};
  const int64_t other = tets[0] == t ? tets[1] : tets[0];
  if (mesh.material(other) == mesh.material(t)) return {FaceSide::Inner, 0};
  return {FaceSide::Interface, mesh.material(other)};
}

// Whether some face at edge cd lies on the outer boundary or on an interface.
bool edgeOnSurface(const ImprovementMesh& mesh, int64_t c, int64_t d) {
  for (int64_t t : mesh.tetsAroundEdge(c, d))
    for (int64_t x : mesh.tet(t)) {
      if (x == c || x == d) continue;
      if (neighbourAcross(mesh, t, c, d, x).side != FaceSide::Inner) return true;
    }
  return false;
}

// Normal of triangle (p, q, r) turned away from `inside` (area-weighted).
Point3 outwardNormal(const Point3& p, const Point3& q, const Point3& r, const Point3& inside) {
  const Point3 n = cross(q - p, r - p);
  return dot(n, inside - p) > 0 ? -1.0 * n : n;
}

// The cap of tet t: corners a, b (the edge the two cap faces share) and c, d (the edge of its
// two inner faces), and what lies across the cap faces.
struct Cap {
  int64_t a = -1, b = -1, c = -1, d = -1;
  FaceNeighbour across;
  bool curved = false;  // flat only within the curved caps' relative flatness
};

// What lies across each face of tet t, the face opposite corner i at i.
using FaceSides = std::array<FaceNeighbour, 4>;
FaceSides sidesOf(const ImprovementMesh& mesh, int64_t t) {
  const TetCorners& k = mesh.tet(t);
  FaceSides sides;
  for (int i = 0; i < 4; ++i) sides[i] = neighbourAcross(mesh, t, k[(i + 1) % 4], k[(i + 2) % 4], k[(i + 3) % 4]);
  return sides;
}

// Two faces of one kind (outer, or one interface) and two inner faces; else a = -1.
Cap capOf(const TetCorners& k, const FaceSides& sides) {
  std::vector<int> capCorners, innerCorners;  // the corner each face is opposite to
  for (int i = 0; i < 4; ++i) (sides[i].side == FaceSide::Inner ? innerCorners : capCorners).push_back(i);
  if (capCorners.size() != 2) return {};
  const FaceNeighbour& first = sides[capCorners[0]];
  const FaceNeighbour& second = sides[capCorners[1]];
  if (first.side != second.side || first.other_material != second.other_material) return {};
  // The face opposite c and the one opposite d are the cap faces; both contain a and b.
  return {k[innerCorners[0]], k[innerCorners[1]], k[capCorners[0]], k[capCorners[1]], first};
}

// The corner shared by the three outer faces of a tet whose fourth face is inner (a fold: the
// outer faces are both triangulations of a quad of the surface, or a pinch), else -1.
int64_t foldCornerOf(const TetCorners& k, const FaceSides& sides) {
  int64_t corner = -1;
  int outer = 0;
  for (int i = 0; i < 4; ++i) {
    if (sides[i].side == FaceSide::Outer) ++outer;
    else if (sides[i].side == FaceSide::Inner) corner = k[i];
  }
  return outer == 3 ? corner : -1;
}

// Flat: the cap faces (abc, abd) face one way and the inner faces (acd, bcd) the other (the two
// triangulations of one convex quad), every corner within `flatness` of their mean plane.
bool isFlat(const std::vector<Point3>& p, const Cap& cap, double flatness) {
  const Point3 &a = p[cap.a], &b = p[cap.b], &c = p[cap.c], &d = p[cap.d];
  const Point3 nabc = outwardNormal(a, b, c, d), nabd = outwardNormal(a, b, d, c);
  const Point3 nacd = outwardNormal(a, c, d, b), nbcd = outwardNormal(b, c, d, a);
  const Point3 sum = nabc + nabd;
  const double length = norm(sum);
  if (!(length > 0)) return false;
  const Point3 normal = (1.0 / length) * sum;
  if (!(dot(nabc, normal) > 0 && dot(nabd, normal) > 0 && dot(nacd, normal) < 0 && dot(nbcd, normal) < 0))
    return false;
  for (const Point3* q : {&b, &c, &d})
    if (std::abs(dot(*q - a, normal)) > flatness) return false;
  return true;
}

class CapRemoval {
 public:
  CapRemoval(TetMesh& mesh, double flatness, double volume_bound, const CurvedCapLimits& curved)
      : work_(mesh), flatness_(flatness), volume_bound_(volume_bound), curved_(curved) {
    for (size_t t = 0; t < mesh.tets.size(); ++t) volume_[mesh.tet_materials[t]] += volumeOf(mesh.tets[t]);
  }

  ImprovementMesh& work() { return work_; }

  // Each flat cap once; returns the changes made. Without `apply` it changes nothing and
  // counts the caps a condition keeps.
  int64_t sweep(FlatCapStats& stats, bool apply) {
    apply_ = apply;
    int64_t changes = 0;
    const int64_t slots = work_.tetSlots();
    for (int64_t t = 0; t < slots; ++t) {
      if (!work_.alive(t)) continue;
      const double flatness = flatnessOf(work_.tet(t));
      if (!thinEnough(work_.tet(t), flatness)) continue;
      const FaceSides sides = sidesOf(work_, t);
      if (const int64_t corner = foldCornerOf(work_.tet(t), sides); corner >= 0) {
        const double h = height(work_.tet(t));
        const bool curved = h > flatness_;
        const bool done = h <= flatness && removeFold(t, corner, curved);
        if (!apply) {
          stats.caps_kept += !done;
        } else if (done) {
          ++changes;
          ++stats.folds_removed;
          stats.curved_caps += curved;
        }
        continue;
      }
      Cap cap = capOf(work_.tet(t), sides);
      if (cap.a < 0 || !isFlat(work_.points(), cap, flatness)) continue;
      cap.curved = !isFlat(work_.points(), cap, flatness_);
      const bool done = cap.across.side == FaceSide::Outer ? removeOuter(t, cap) : flipInterface(t, cap);
      if (!apply) {
        stats.caps_kept += !done;
      } else if (done) {
        ++changes;
        ++(cap.across.side == FaceSide::Outer ? stats.boundary_caps_removed : stats.interface_caps_flipped);
        stats.curved_caps += cap.curved;
      }
    }
    return changes;
  }

  double largestVolumeChange(bool curved) const {
    double largest = 0;
    for (const auto& [material, moved] : curved ? curved_moved_ : moved_)
      largest = std::max(largest, moved / volume_.at(material));
    return largest;
  }

 private:
  double volumeOf(const TetCorners& t) const { return tetVolume(work_.points(), t); }

  // Cheap first look before the face lookups. isFlat puts the corners in a slab of width
  // w = 2 flatness; the faces facing one way cover the tet's shadow on the slab, at most twice
  // the largest face, so the volume is at most 2w/3 of the largest face and the height over it
  // at most 2w.
  bool thinEnough(const TetCorners& t, double flatness) const {
    const double h = height(t);
    return h >= 0 && h <= 4 * flatness;
  }

  // The tet's height over its largest face; -1 when every face is degenerate.
  double height(const TetCorners& t) const {
    const auto& p = work_.points();
    double largest = 0;
    for (int i = 0; i < 4; ++i) {
      const Point3 &a = p[t[(i + 1) % 4]], &b = p[t[(i + 2) % 4]], &c = p[t[(i + 3) % 4]];
      largest = std::max(largest, 0.5 * norm(cross(b - a, c - a)));
    }
    return largest > 0 ? 3 * volumeOf(t) / largest : -1;
  }

  // The absolute flatness, or with curved caps that share of the tet's longest edge if larger.
  double flatnessOf(const TetCorners& t) const {
    if (!(curved_.relative_flatness > 0)) return flatness_;
    const auto& p = work_.points();
    double longest = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) longest = std::max(longest, distance(p[t[i]], p[t[j]]));
    return std::max(flatness_, curved_.relative_flatness * longest);
  }

  // Within the bound of the change's kind (on a flat or a curved piece).
  bool withinVolumeBound(bool curved, int material, double volume) const {
    const auto& moved = curved ? curved_moved_ : moved_;
    const auto it = moved.find(material);
    const double before = it == moved.end() ? 0 : it->second;
    return before + volume <= (curved ? curved_.volume_bound : volume_bound_) * volume_.at(material);
  }

  void countVolume(bool curved, int material, double volume) {
    (curved ? curved_moved_ : moved_)[material] += volume;
  }

  // A flat fold taken out: its inner face becomes the boundary. The edges at `corner` lose
  // the tet's two outer faces at each, so they keep two boundary faces (or vanish with the
  // tet, unless one is a feature edge). The corner must stay in a tet, and its other tets one
  // fan (else the surface would pinch there).
  bool removeFold(int64_t t, int64_t corner, bool curved) {
    const int material = work_.material(t);
    for (int64_t v : work_.tet(t))
      if (v != corner && work_.isProtectedEdge(corner, v) && work_.tetsAroundEdge(corner, v).size() == 1) return false;
    if (!oneFanWithout(corner, t)) return false;
    const double volume = volumeOf(work_.tet(t));
    if (!withinVolumeBound(curved, material, volume)) return false;
    if (!apply_) return true;
    work_.replace({t}, {}, material);
    countVolume(curved, material, volume);
    return true;
  }

  // Whether v's tets other than `removed` are at least one and connected through faces at v.
  bool oneFanWithout(int64_t v, int64_t removed) const {
    std::vector<int64_t> rest;
    for (int64_t t : work_.tetsOf(v))
      if (t != removed) rest.push_back(t);
    if (rest.empty()) return false;
    std::vector<char> reached(rest.size(), 0);
    std::vector<size_t> stack{0};
    reached[0] = 1;
    auto sharedCorners = [&](int64_t x, int64_t y) {
      int n = 0;
      for (int64_t a : work_.tet(x))
        for (int64_t b : work_.tet(y)) n += a == b;
      return n;
    };
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      for (size_t j = 0; j < rest.size(); ++j)
        if (!reached[j] && sharedCorners(rest[i], rest[j]) == 3) {
          reached[j] = 1;
          stack.push_back(j);
        }
    }
    return std::all_of(reached.begin(), reached.end(), [](char r) { return r != 0; });
  }

  // The edge ab disappears with the tet unless another tet has it; c and d stay in the inner
  // faces' neighbours, a and b too, so every vertex stays used.
  bool removeOuter(int64_t t, const Cap& cap) {
    const int material = work_.material(t);
    if (work_.isProtectedEdge(cap.a, cap.b) && work_.tetsAroundEdge(cap.a, cap.b).size() == 1) return false;
    if (edgeOnSurface(work_, cap.c, cap.d)) return false;
    const double volume = volumeOf(work_.tet(t));
    if (!withinVolumeBound(cap.curved, material, volume)) return false;
    if (!apply_) return true;
    work_.replace({t}, {}, material);
    countVolume(cap.curved, material, volume);
    return true;
  }

  // The tets around ab are this one (material A) and a closed fan of material B; all of them
  // become B, triangulated without ab, so the interface triangles abc, abd become acd, bcd.
  bool flipInterface(int64_t t, const Cap& cap) {
    const int own = work_.material(t), other = cap.across.other_material;
    if (work_.isProtectedEdge(cap.a, cap.b)) return false;
    if (edgeOnSurface(work_, cap.c, cap.d)) return false;
    const std::vector<int64_t> ring = work_.tetsAroundEdge(cap.a, cap.b);
    // The size bound comes from B's tets only (the flat tet's circumradius would admit
    // anything), with room for the flat tet's height added to their region (rounding alone
    // makes the mirror image of a tet across the flat quad 1e-13 bigger).
    SizeBound bound;
    const auto& p = work_.points();
    for (int64_t r : ring) {
      if (r == t) continue;
      if (work_.material(r) != other) return false;
      const TetCorners& k = work_.tet(r);
      bound.include(tetSize(p[k[0]], p[k[1]], p[k[2]], p[k[3]]));
    }
    bound.circumradius *= 1 + kSizeSlack;
    bound.radius_edge_ratio *= 1 + kSizeSlack;
    std::vector<TetCorners> made;
    if (!(triangulateEdgeRing(work_, cap.a, cap.b, ring, bound, other, made) > work_.quality(t))) return false;
    const double volume = volumeOf(work_.tet(t));
    if (!withinVolumeBound(cap.curved, own, volume) || !withinVolumeBound(cap.curved, other, volume)) return false;
    if (!apply_) return true;
    work_.replace(ring, made, other);
    countVolume(cap.curved, own, volume);
    countVolume(cap.curved, other, volume);
    return true;
  }

  ImprovementMesh work_;
  double flatness_, volume_bound_;
  CurvedCapLimits curved_;
  bool apply_ = true;
  std::map<int, double> volume_;        // per material, before
  std::map<int, double> moved_;         // per material, summed volume gained or lost by flat caps
  std::map<int, double> curved_moved_;  // the same by curved caps
};

}  // namespace

FlatCapStats removeFlatCaps(TetMesh& mesh, double flatness, double volume_bound, const CurvedCapLimits& curved) {
  FlatCapStats stats;
  CapRemoval removal(mesh, flatness, volume_bound, curved);
  int64_t changes = 0;
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    const int64_t made = removal.sweep(stats, true);
    changes += made;
    if (made == 0) break;
  }
  removal.sweep(stats, false);
  stats.largest_volume_change = removal.largestVolumeChange(false);
  stats.largest_curved_volume_change = removal.largestVolumeChange(true);
  if (changes == 0) return stats;
  removal.work().writeBack(mesh);
  mesh.boundary = extractBoundary(mesh);
  return stats;
}

}  // namespace oraclemesh
