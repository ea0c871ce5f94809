#include "domain/HierarchicalOracle.h"

#include "Error.h"

namespace oraclemesh {

HierarchicalOracle::HierarchicalOracle(std::vector<OracleEntry> entries) : entries_(std::move(entries)) {
  if (entries_.empty())
    throw InputError("the job has no inputs: add at least one solid with role 'material'");
  bool anyMaterial = false;
  for (const OracleEntry& e : entries_) {
    if (!e.source) throw InputError("an input has no geometry: give it a file, BREP text or a sphere");
    if (e.role == Role::Material) {
      if (e.material <= 0)
        throw InputError("input '" + e.source->name() + "' has material id " + std::to_string(e.material) +
                         ": material ids must be positive integers (1, 2, ...)");
      anyMaterial = true;
      bbox_.add(e.source->bbox());
    }
  }
  if (!anyMaterial)
    throw InputError("all inputs have role 'cut', so nothing is left to mesh: give at least one input role 'material'");
}

int HierarchicalOracle::decidingEntry(const Point3& p) const {
  if (!bbox_.contains(p)) return -1;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Source& s = *entries_[i].source;
    // The bbox test is the cheap reject that keeps most queries away from the exact test.
    if (s.bbox().contains(p) && s.inside(p)) return static_cast<int>(i);
  }
  return -1;
}

int HierarchicalOracle::label(const Point3& p) const {
  const int i = decidingEntry(p);
  if (i < 0 || entries_[i].role == Role::Cut) return 0;
  return entries_[i].material;
}

bool HierarchicalOracle::coveredByHigherEntry(const Point3& p, int entry) const {
  const double tol = 1e3 * tolerance();  // "strictly inside": farther than this from the boundary
  for (int i = 0; i < entry && i < static_cast<int>(entries_.size()); ++i) {
    const Source& s = *entries_[i].source;
    if (!s.bbox().contains(p) || !s.inside(p)) continue;
    if (s.project(p).distance > tol) return true;
  }
  return false;
}

BoundaryProjection HierarchicalOracle::projectOnBoundary(const Point3& p, int* entry) const {
  BoundaryProjection best;
  int bestEntry = -1;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const BoundaryProjection q = entries_[i].source->project(p);
    if (q.distance < best.distance) {
      best = q;
      bestEntry = static_cast<int>(i);
    }
  }
  if (entry) *entry = bestEntry;
  return best;
}

}  // namespace oraclemesh
