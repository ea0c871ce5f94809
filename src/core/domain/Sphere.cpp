#include "domain/Sphere.h"

#include <cmath>

#include "Error.h"

namespace oraclemesh {

Sphere::Sphere(const Point3& center, double radius, std::string name)
    : center_(center), radius_(radius), name_(std::move(name)) {
  if (!(std::isfinite(radius) && radius > 0))
    throw InputError("input '" + name_ + "' is a sphere with radius " + std::to_string(radius) +
                     ": give a positive radius in model units (mm)");
  for (double c : center)
    if (!std::isfinite(c))
      throw InputError("input '" + name_ + "' is a sphere whose center is not a finite point: give three numbers");
}

Bbox Sphere::bbox() const {
  Bbox b;
  b.add(center_ - Point3{radius_, radius_, radius_});
  b.add(center_ + Point3{radius_, radius_, radius_});
  return b;
}

bool Sphere::inside(const Point3& p) const {
  const Point3 d = p - center_;
  return dot(d, d) <= radius_ * radius_;
}

BoundaryProjection Sphere::project(const Point3& p) const {
  BoundaryProjection result;
  const Point3 d = p - center_;
  const double r = norm(d);
  // Every boundary point is nearest to the center; any one will do, a fixed one keeps runs
  // deterministic.
  const Point3 direction = r > 0 ? (1.0 / r) * d : Point3{1, 0, 0};
  result.point = center_ + radius_ * direction;
  result.patch = 0;
  result.distance = std::abs(r - radius_);
  return result;
}

std::vector<BoundarySample> Sphere::boundarySamples(double spacing) const {
  // A Fibonacci lattice: nearly uniform, deterministic, one point per spacing^2 of area.
  constexpr double kPi = 3.14159265358979323846;
  const double area = 4 * kPi * radius_ * radius_;
  size_t count = 1;
  if (spacing > 0 && std::isfinite(spacing))
    count = static_cast<size_t>(std::clamp(std::ceil(area / (spacing * spacing)), 1.0, 1e7));
  else
    count = 1000;
  const double golden = kPi * (3 - std::sqrt(5.0));
  std::vector<BoundarySample> samples;
  samples.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const double z = 1 - (2 * (i + 0.5)) / static_cast<double>(count);
    const double ring = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = golden * static_cast<double>(i);
    const Point3 normal{ring * std::cos(phi), ring * std::sin(phi), z};
    samples.push_back({center_ + radius_ * normal, normal, 0});
  }
  return samples;
}

std::vector<BoundaryCrossing> Sphere::crossings(const Point3& a, const Point3& b) const {
  std::vector<BoundaryCrossing> result;
  const Point3 d = b - a;
  const Point3 m = a - center_;
  // t^2 dd + 2 t md + (mm - r^2) = 0, solved without cancellation: the larger-magnitude root
  // from the usual formula, the other from the product of the roots.
  const double dd = dot(d, d);
  if (dd == 0.0) return result;
  const double md = dot(m, d);
  const double c = dot(m, m) - radius_ * radius_;
  const double discriminant = md * md - dd * c;
  if (!(discriminant > 0.0)) return result;  // misses or only touches
  const double q = -(md + std::copysign(std::sqrt(discriminant), md));
  double t0 = q / dd, t1 = q != 0.0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  auto add = [&](double t, bool entering) {
    if (t < 0.0 || t > 1.0) return;
    BoundaryCrossing crossing;
    crossing.t = t;
    crossing.point = a + t * d;
    crossing.patch = 0;
    crossing.entering = entering;
    result.push_back(crossing);
  };
  add(t0, true);
  add(t1, false);
  return result;
}

double Sphere::volume() const {
  constexpr double kPi = 3.14159265358979323846;
  return 4.0 / 3.0 * kPi * radius_ * radius_ * radius_;
}

}  // namespace oraclemesh
