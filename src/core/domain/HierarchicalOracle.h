#pragma once
// The hierarchical oracle (thesis §4.1): overlapping inputs composed by priority, without
// Boolean operations. Entry 0 has the highest priority. A `material` entry claims the
// points inside it that no higher entry claimed; a `cut` entry makes the points inside it
// exterior for itself and every lower entry.
#include <vector>

#include "domain/Source.h"

namespace oraclemesh {

enum class Role { Material, Cut };

// A place where a segment a->b crosses the boundary of the composite domain: the material
// label changes there (label 0 = outside, as label()).
struct CompositeCrossing {
  double t = 0.0;  // the point is a + t (b - a), t in [0, 1]
  Point3 point{};
  int entry = -1;  // index of the entry whose boundary is crossed
  int patch = -1;  // that entry's boundary patch (B-rep face index, ...)
  int labelBefore = 0;
  int labelAfter = 0;
};

struct OracleEntry {
  SourcePtr source;
  Role role = Role::Material;
  int material = 0;  // > 0 for Role::Material; 0 for Role::Cut
};

class HierarchicalOracle {
 public:
  // Throws InputError when there is no material entry or an entry is malformed.
  explicit HierarchicalOracle(std::vector<OracleEntry> entries);

  // Material id at p; 0 = outside the composite domain.
  int label(const Point3& p) const;
  // Index of the entry that decides p's label, or -1 when no entry contains p.
  int decidingEntry(const Point3& p) const;
  // True when p is strictly inside (not just on the boundary) an entry with a higher
  // priority than `entry`, i.e. whatever entry `entry` says about p is overridden.
  bool coveredByHigherEntry(const Point3& p, int entry) const;
  // Distance from p to the closure of `material`'s entries: 0 inside one, else the distance
  // to the nearest boundary of those whose box comes within `reach` of p (infinity: none).
  double distanceToMaterial(const Point3& p, int material, double reach) const;

  const std::vector<OracleEntry>& entries() const { return entries_; }
  // Bounding box of the material entries (cuts cannot add volume).
  const Bbox& bbox() const { return bbox_; }
  double diagonal() const { return bbox_.diagonal(); }
  // Geometric tolerance for "on the boundary" decisions, relative to the model size.
  double tolerance() const { return 1e-9 * bbox_.diagonal(); }
  // Nearest point on any entry's boundary (used to put mesh nodes exactly on the CAD faces).
  // `entry` receives the index of the entry whose boundary was nearest.
  BoundaryProjection projectOnBoundary(const Point3& p, int* entry = nullptr) const;

  // Where the segment a->b changes label, sorted by t. Built from the entries' own exact
  // crossings (Source::crossings), without sampling: each entry's inside/outside state along
  // the segment follows from its crossings (entering or leaving), the composite label from
  // the states by priority as in label() (a cut entry inside yields 0 for itself and every
  // lower entry), and only the crossings where that label changes are kept. Crossings of
  // several entries closer than tolerance() along the segment (coincident faces, a pin
  // ending on a plate face) are one place: its entry is the highest-priority entry crossed
  // there that decides the label on one side. An entry whose boundary the segment does not
  // cross keeps the state of the segment's midpoint. An end that is not finite is an Error.
  std::vector<CompositeCrossing> crossings(const Point3& a, const Point3& b) const;

 private:
  std::vector<OracleEntry> entries_;
  Bbox bbox_;
};

}  // namespace oraclemesh
