#pragma once
// The fineness presets of the sizing field, like Netgen's in FreeCAD (very coarse .. very
// fine): how many segments a full circle gets, how fast sizes may grow away from small
// features, and how many sizes fit through the thickness of a wall.
#include <string>

namespace oraclemesh {

struct FinenessPreset {
  const char* name;
  int segments_per_circle;   // curved faces: a full circle of their tightest radius
  double grading;            // growth of the size per unit of distance (Lipschitz constant)
  double sizes_per_thickness;  // wall thickness / size, at least
};

inline constexpr FinenessPreset kFinenessPresets[] = {
    {"very_coarse", 6, 0.7, 1.5}, {"coarse", 8, 0.5, 2},       {"moderate", 12, 0.3, 3},
    {"fine", 18, 0.2, 4},         {"very_fine", 24, 0.1, 6},
};

// What an unset criteria.fineness means.
inline constexpr const char* kDefaultFineness = "moderate";

// nullptr for an unknown name.
inline const FinenessPreset* findFineness(const std::string& name) {
  for (const FinenessPreset& p : kFinenessPresets)
    if (name == p.name) return &p;
  return nullptr;
}

}  // namespace oraclemesh
