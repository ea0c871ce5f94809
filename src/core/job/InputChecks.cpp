#include "job/InputChecks.h"

#include <sstream>
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

std::string whatTheInputsEnclose(const JobSpec& job, const HierarchicalOracle& oracle) {
  std::ostringstream out;
  out.precision(4);
  out << " The material inputs:";
  int listed = 0;
  const int kListed = 8;
  int materials = 0;
  for (const OracleEntry& e : oracle.entries()) {
    if (e.role != Role::Material) continue;
    if (++materials > kListed) continue;
    const Source& source = *e.source;
    const Bbox box = source.bbox();
    const double boxVolume = (box.max[0] - box.min[0]) * (box.max[1] - box.min[1]) * (box.max[2] - box.min[2]);
    out << (listed++ ? "; " : " ") << "'" << source.name() << "'";
    // "<input>#k" names the k-th solid of the job input <input>.
    const std::string input = source.name().substr(0, source.name().rfind('#'));
    for (const InputSpec& spec : job.inputs)
      if (spec.name == input && !spec.file.empty()) out << " (file " << spec.file << ")";
    out << " encloses " << source.volume() << " model units^3 in a box of " << boxVolume;
  }
  if (materials > kListed) out << "; and " << materials - kListed << " more";
  out << ". A part whose CAD is invalid can enclose a small part of its box or nothing: check each with "
         "Part > Check geometry in FreeCAD, repair it or export it again.";
  return out.str();
}

}  // namespace oraclemesh
