#pragma once
// Hand-made triangle surfaces and label images for the tests of inputs without exact faces.
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "Geometry.h"

namespace oraclemesh::test {

struct Triangles {
  std::vector<Point3> points;
  std::vector<std::array<int64_t, 3>> triangles;  // outward
};

// A closed cylinder of `segments` sides along z from `base` up `height`: strips of two
// triangles each (cut along alternate diagonals, so the points' triangles are not symmetric)
// and fans to the caps' centres.
inline Triangles tessellatedCylinder(const Point3& base, double radius, double height, int segments) {
  Triangles out;
  for (int z = 0; z < 2; ++z)
    for (int k = 0; k < segments; ++k) {
      const double a = 2 * M_PI * k / segments;
      out.points.push_back({base[0] + radius * std::cos(a), base[1] + radius * std::sin(a), base[2] + z * height});
    }
  const int64_t bottom = 2 * segments, top = bottom + 1;
  out.points.push_back(base);
  out.points.push_back({base[0], base[1], base[2] + height});
  for (int64_t k = 0; k < segments; ++k) {
    const int64_t next = (k + 1) % segments, a = k, b = next, c = segments + next, d = segments + k;
    if (k % 2 == 0) {
      out.triangles.push_back({a, b, c});
      out.triangles.push_back({a, c, d});
    } else {
      out.triangles.push_back({a, b, d});
      out.triangles.push_back({b, c, d});
    }
    out.triangles.push_back({bottom, b, a});
    out.triangles.push_back({top, d, c});
  }
  return out;
}

// The volume tessellatedCylinder encloses.
inline double tessellatedCylinderVolume(double radius, double height, int segments) {
  return 0.5 * segments * radius * radius * std::sin(2 * M_PI / segments) * height;
}

// An axis-aligned box from `low`, as 12 triangles.
inline Triangles triangleBox(const Point3& low, double x, double y, double z) {
  Triangles out;
  for (int k = 0; k < 8; ++k)
    out.points.push_back({low[0] + ((k == 1 || k == 2 || k == 5 || k == 6) ? x : 0),
                          low[1] + ((k == 2 || k == 3 || k == 6 || k == 7) ? y : 0), low[2] + (k >= 4 ? z : 0)});
  out.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                   {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  return out;
}

// A job input of `t` as a "surface" (points and triangles in the job).
inline nlohmann::json surfaceInput(const std::string& name, const Triangles& t, int material) {
  nlohmann::json points = nlohmann::json::array(), triangles = nlohmann::json::array();
  for (const Point3& p : t.points) points.push_back({p[0], p[1], p[2]});
  for (const auto& c : t.triangles) triangles.push_back({c[0], c[1], c[2]});
  return {{"name", name}, {"surface", {{"points", points}, {"triangles", triangles}}}, {"material", material}};
}

}  // namespace oraclemesh::test
