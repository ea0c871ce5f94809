#include "job/InputChecks.h"

#include <string>

#include "Error.h"

namespace oraclemesh {

namespace {

constexpr int kGridSteps = 12;  // points per axis probed in each material entry's box

}  // namespace

void checkCutsLeaveMaterial(const HierarchicalOracle& oracle) {
  const std::vector<OracleEntry>& entries = oracle.entries();
  bool anyCut = false;
  for (const OracleEntry& e : entries) anyCut = anyCut || e.role == Role::Cut;
  if (!anyCut) return;
  // A grid in each material entry's box: material left anywhere ends the check at once (the
  // common case costs a few queries); a part thinner than the grid spacing gives no probe
  // inside it, and then the engines' own message stands.
  int removingCut = -1;
  for (const OracleEntry& e : entries) {
    if (e.role != Role::Material) continue;
    const Bbox box = e.source->bbox();
    for (int i = 0; i < kGridSteps; ++i)
      for (int j = 0; j < kGridSteps; ++j)
        for (int k = 0; k < kGridSteps; ++k) {
          const int step[3] = {i, j, k};
          Point3 p;
          for (int a = 0; a < 3; ++a)
            p[a] = box.min[a] + (step[a] + 0.5) / kGridSteps * (box.max[a] - box.min[a]);
          if (!e.source->inside(p)) continue;
          const int decider = oracle.decidingEntry(p);
          if (decider < 0 || entries[decider].role == Role::Material) return;
          if (removingCut < 0) removingCut = decider;
        }
  }
  if (removingCut < 0) return;
  std::string materials;
  for (const OracleEntry& e : entries)
    if (e.role == Role::Material) materials += (materials.empty() ? "'" : ", '") + e.source->name() + "'";
  throw InputError("the cut '" + entries[removingCut].source->name() + "' removes everything: every material input (" +
                   materials + ") lies inside a cut listed above it, so nothing is left to mesh: move or shrink the "
                   "cut, or list it below the inputs it must not remove (a cut removes what lies inside it from "
                   "itself and every input listed after it)");
}

}  // namespace oraclemesh
