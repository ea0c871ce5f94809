#pragma once
// How two parts (materials) of one mesh are joined where they touch (issue 19): the job's
// "interfaces" setting resolved to material ids, read by the interface split and the writers.
#include <map>
#include <utility>

namespace oraclemesh {

// bonded: shared nodes (one conformal mesh). The others give each part its own nodes along
// the common faces (mesh/InterfaceSplit); the INP then ties them (tied), puts a CalculiX
// surface-to-surface contact pair between them (contact) or leaves them free (separate).
enum class InterfaceKind { Bonded, Tied, Contact, Separate };

// The job's names: "bonded", "tied", "contact", "separate".
const char* interfaceKindName(InterfaceKind kind);

struct InterfaceBehaviour {
  InterfaceKind kind = InterfaceKind::Bonded;
  double friction = 0;  // Coulomb coefficient, contact only; 0 = frictionless
  // Contact only: the slope of the linear pressure-overclosure law (pressure per overclosure,
  // force / length^3) as the job gives it; 0 = the writer's steel default (see
  // InterfaceConstraint::contact_stiffness).
  double contact_stiffness = 0;
  // The part whose faces are the master side of a tie or contact; 0 = chosen by the writer
  // (the coarser side, see writeInp).
  int master_material = 0;
};

struct InterfacePlan {
  InterfaceBehaviour default_behaviour;
  std::map<std::pair<int, int>, InterfaceBehaviour> pairs;  // key: (smaller, larger material id)

  InterfaceBehaviour between(int a, int b) const {
    const auto it = pairs.find(a < b ? std::make_pair(a, b) : std::make_pair(b, a));
    return it != pairs.end() ? it->second : default_behaviour;
  }
  bool bonded(int a, int b) const { return between(a, b).kind == InterfaceKind::Bonded; }
  // Whether any pair may need its own nodes (so the split has work to do).
  bool splitsAny() const {
    if (default_behaviour.kind != InterfaceKind::Bonded) return true;
    for (const auto& [pair, behaviour] : pairs)
      if (behaviour.kind != InterfaceKind::Bonded) return true;
    return false;
  }
};

inline const char* interfaceKindName(InterfaceKind kind) {
  switch (kind) {
    case InterfaceKind::Tied: return "tied";
    case InterfaceKind::Contact: return "contact";
    case InterfaceKind::Separate: return "separate";
    default: return "bonded";
  }
}

}  // namespace oraclemesh
