#include "job/InterfaceSettings.h"

#include <map>
#include <set>

#include "Error.h"

namespace oraclemesh {

namespace {

std::string knownParts(const MaterialNames& names) {
  std::string list;
  for (const auto& [material, name] : names) list += (list.empty() ? "'" : ", '") + name + "'";
  return list;
}

std::pair<int, int> orderedPair(int a, int b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); }

}  // namespace

InterfacePlan resolveInterfaces(const InterfacesSpec& spec, const MaterialNames& names) {
  std::map<std::string, int> materialOf;
  for (const auto& [material, name] : names) materialOf.emplace(name, material);
  InterfacePlan plan;
  plan.default_behaviour.kind = spec.default_kind;
  plan.default_behaviour.contact_stiffness = spec.default_contact_stiffness;
  for (size_t i = 0; i < spec.pairs.size(); ++i) {
    const InterfacePairSpec& pair = spec.pairs[i];
    int ids[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      const auto it = materialOf.find(pair.between[k]);
      if (it == materialOf.end())
        throw InputError("interfaces.pairs[" + std::to_string(i) + "].between[" + std::to_string(k) + "] = '" +
                         pair.between[k] + "' is no part of the model: the parts are " + knownParts(names) +
                         " (as report.inputs and report.interfaces name them; inputs of one material id are one "
                         "part, named with '+')");
      ids[k] = it->second;
    }
    InterfaceBehaviour behaviour = pair.behaviour;
    if (!pair.master.empty()) behaviour.master_material = materialOf.at(pair.master);
    if (behaviour.kind == InterfaceKind::Contact && behaviour.contact_stiffness == 0)
      behaviour.contact_stiffness = spec.default_contact_stiffness;
    plan.pairs[orderedPair(ids[0], ids[1])] = behaviour;
  }
  return plan;
}

std::vector<std::string> interfaceWarnings(const InterfacePlan& plan, const std::vector<MeshSurface>& surfaces,
                                           const MaterialNames& names) {
  std::set<std::pair<int, int>> touching;
  for (const MeshSurface& s : surfaces)
    if (s.other_material != 0) touching.insert(orderedPair(s.material, s.other_material));
  std::vector<std::string> warnings;
  for (const auto& [pair, behaviour] : plan.pairs)
    if (!touching.count(pair))
      warnings.push_back("interfaces: the parts '" + materialName(names, pair.first) + "' and '" +
                         materialName(names, pair.second) + "' share no face in the mesh, so their \"" +
                         interfaceKindName(behaviour.kind) + "\" setting acts at most where they meet along an "
                         "edge or at a point (report.interfaces lists the pairs that touch)");
  return warnings;
}

std::vector<std::string> keptJoinedWarnings(const InterfacePlan& plan, const InterfaceSplitStats& split,
                                            const MaterialNames& names) {
  std::vector<std::string> warnings;
  for (const auto& [pair, kept] : split.kept_joined) {
    const std::string a = "'" + materialName(names, pair.first) + "'", c = "'" + materialName(names, pair.second) + "'";
    std::string through, fix;
    for (int b : kept.through) {
      const std::string name = "'" + materialName(names, b) + "'";
      through += (through.empty() ? "" : ", ") + name;
      fix += (fix.empty() ? "" : ", ") + a + "-" + name + " or " + name + "-" + c;
    }
    warnings.push_back("interfaces: the parts " + a + " and " + c + " (\"" +
                       interfaceKindName(plan.between(pair.first, pair.second).kind) + "\") stay joined at " +
                       std::to_string(kept.nodes) + " nodes, where both meet " + through +
                       ", bonded to both: a node shared with a part bonded to both cannot be split between "
                       "them; make " + fix + " not bonded to part them there too");
  }
  return warnings;
}

}  // namespace oraclemesh
