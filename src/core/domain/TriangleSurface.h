#pragma once
// A watertight triangle surface input (STL ASCII/binary, OBJ, OFF, or triangles in memory
// such as a FreeCAD Mesh): scanned bones, exported meshes. Validated before any query:
// closed, manifold, consistently oriented, not self-intersecting. A surface that is inward
// as a whole is turned round silently; a triangle flipped against its neighbours is an error.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "domain/Source.h"

namespace oraclemesh {

class TriangleSurface : public Source {
 public:
  // InputError naming `name`, the file and the defect (empty, unreadable, holes with their
  // border edge count, non-manifold, flipped triangles by number, self-intersections with a
  // location).
  static std::shared_ptr<TriangleSurface> fromFile(const std::string& path, const std::string& name);
  // Triangles as 0-based indices into `points` (the job's "surface" input); the same checks.
  static std::shared_ptr<TriangleSurface> fromTriangles(std::vector<Point3> points,
                                                        const std::vector<std::array<int64_t, 3>>& triangles,
                                                        const std::string& name);
  ~TriangleSurface() override;

  const std::string& name() const override;
  Bbox bbox() const override;
  bool inside(const Point3& p) const override;
  BoundaryProjection project(const Point3& p) const override;  // patch = triangle index
  std::vector<BoundarySample> boundarySamples(double spacing) const override;
  // Segment/triangle intersections on the AABB tree; patch = index of the connected
  // component of the surface hit. A segment through an edge or a vertex gives one crossing
  // (or none when it only touches the surface there).
  std::vector<BoundaryCrossing> crossings(const Point3& a, const Point3& b) const override;
  double volume() const override;
  size_t triangleCount() const;
  // The validated surface: its points and its triangles (0-based, outward).
  void outwardTriangles(std::vector<Point3>& points, std::vector<std::array<int64_t, 3>>& triangles) const;

 private:
  TriangleSurface();
  // The checks shared by every way in; triangleName(i) names input triangle i in messages.
  static std::shared_ptr<TriangleSurface> validated(std::vector<Point3> points,
                                                    const std::vector<std::array<int64_t, 3>>& triangles,
                                                    const std::string& name, const std::string& what,
                                                    const std::function<std::string(std::size_t)>& triangleName);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace oraclemesh
