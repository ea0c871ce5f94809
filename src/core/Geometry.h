#pragma once
// Plain geometric value types shared by every layer. The core's interfaces use these
// instead of CGAL or OpenCASCADE types so that headers stay cheap to include.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace oraclemesh {

using Point3 = std::array<double, 3>;

inline Point3 operator+(const Point3& a, const Point3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Point3 operator-(const Point3& a, const Point3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Point3 operator*(double s, const Point3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Point3 cross(const Point3& a, const Point3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Point3& a) { return std::sqrt(dot(a, a)); }
inline bool isFinite(const Point3& a) { return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]); }
inline double distance(const Point3& a, const Point3& b) { return norm(a - b); }
// The unit vector along a; the zero vector for the zero vector.
inline Point3 unit(const Point3& a) {
  const double n = norm(a);
  return n > 0 ? (1.0 / n) * a : Point3{0, 0, 0};
}

// Distance from p to the segment ab; `parameter` (if given) gets the nearest point's position
// along it, 0 at a and 1 at b.
inline double distanceToSegment(const Point3& p, const Point3& a, const Point3& b, double* parameter = nullptr) {
  const Point3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  if (parameter) *parameter = t;
  return distance(p, a + t * ab);
}

// The point of a polyline nearest to p: its distance, the segment it lies on and its position
// along that segment (0 at the segment's start, 1 at its end). A single point is its own nearest.
struct PolylineFoot {
  Point3 point{};
  double distance = std::numeric_limits<double>::infinity();
  size_t segment = 0;
  double along = 0;
};

inline PolylineFoot nearestOnPolyline(const std::vector<Point3>& polyline, const Point3& p) {
  PolylineFoot foot;
  if (polyline.size() == 1) foot.point = polyline.front(), foot.distance = distance(p, polyline.front());
  for (size_t i = 0; i + 1 < polyline.size(); ++i) {
    double t = 0;
    const double d = distanceToSegment(p, polyline[i], polyline[i + 1], &t);
    if (d < foot.distance) foot = {polyline[i] + t * (polyline[i + 1] - polyline[i]), d, i, t};
  }
  return foot;
}

struct Bbox {
  Point3 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity()};
  Point3 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
             -std::numeric_limits<double>::infinity()};

  bool empty() const { return min[0] > max[0]; }
  void add(const Point3& p) {
    for (int i = 0; i < 3; ++i) {
      min[i] = std::min(min[i], p[i]);
      max[i] = std::max(max[i], p[i]);
    }
  }
  void add(const Bbox& b) {
    if (b.empty()) return;
    add(b.min);
    add(b.max);
  }
  // Written so that a NaN coordinate is never contained: every query that starts with this
  // test then keeps a NaN point (a rounding accident upstream) away from CGAL's exact
  // predicates and OpenCASCADE.
  bool contains(const Point3& p, double margin = 0) const {
    for (int i = 0; i < 3; ++i)
      if (!(p[i] >= min[i] - margin && p[i] <= max[i] + margin)) return false;
    return true;
  }
  double diagonal() const { return empty() ? 0.0 : distance(min, max); }
};

}  // namespace oraclemesh
