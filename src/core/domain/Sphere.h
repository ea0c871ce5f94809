#pragma once
// The implicit sphere of the thesis: exact answers in closed form.
#include <string>

#include "domain/Source.h"

namespace oraclemesh {

class Sphere : public Source {
 public:
  // InputError when the radius is not a positive finite number.
  Sphere(const Point3& center, double radius, std::string name);

  const std::string& name() const override { return name_; }
  Bbox bbox() const override;
  bool inside(const Point3& p) const override;
  BoundaryProjection project(const Point3& p) const override;
  std::vector<BoundarySample> boundarySamples(double spacing) const override;
  // Closed form: the roots of |a + t (b - a) - center|^2 = radius^2 in [0, 1]; a tangent
  // segment (double root) does not cross and gives nothing. Patch 0.
  std::vector<BoundaryCrossing> crossings(const Point3& a, const Point3& b) const override;
  double volume() const override;

 private:
  Point3 center_;
  double radius_;
  std::string name_;
};

}  // namespace oraclemesh
