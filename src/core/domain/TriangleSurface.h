#pragma once
// A watertight triangle surface input (STL ASCII/binary, OBJ, OFF): scanned bones, exported
// meshes. Validated before any query: closed, manifold, not self-intersecting; the
// orientation is fixed silently so the normals point outward.
#include <memory>
#include <string>

#include "domain/Source.h"

namespace oraclemesh {

class TriangleSurface : public Source {
 public:
  // InputError naming `name`, the file and the defect (empty, unreadable, holes with their
  // border edge count, non-manifold, self-intersections with a location).
  static std::shared_ptr<TriangleSurface> fromFile(const std::string& path, const std::string& name);
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

 private:
  TriangleSurface();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace oraclemesh
