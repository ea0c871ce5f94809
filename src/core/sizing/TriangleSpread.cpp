#include "sizing/TriangleSpread.h"

#include <algorithm>
#include <cmath>

namespace oraclemesh {

namespace {

using Weights = std::array<double, 2>;

// A triangle whose longest edge squared exceeds this many times its area is a needle: its even
// grid would hold more points than its rows. Equilateral triangles (2.3), right isosceles
// ones (4) and the halves of equilateral ones (4.6) are not.
constexpr double kNeedleLengthSquaredPerArea = 8;

// A needle's rows lie at most this many spacings apart, their points at most this many along
// them: a point of the needle lies within sqrt(0.4^2 + 0.41^2) = 0.573 < 1 / sqrt(3) spacings
// of the row below it (the longest edge's ends have acute angles, so a point projects onto
// that row within its ends).
constexpr double kRowsApartPerSpacing = 0.4;
constexpr double kAlongRowPerSpacing = 0.82;

// Steps of at most `step` over `length`, at least one and at most `most`.
size_t stepsOver(double length, double step, double most) {
  const double steps = std::ceil(length / step);
  return steps < 1 || !std::isfinite(steps) ? size_t(1) : static_cast<size_t>(std::min(steps, most));
}

}  // namespace

std::vector<Weights> spreadOverTriangle(const Point3 (&corners)[3], double spacing, size_t maxPoints) {
  const Weights weightOf[3] = {{1, 0}, {0, 1}, {0, 0}};
  int longest = 0;  // the edge from corner k to corner k + 1
  double longestLength = -1;
  for (int k = 0; k < 3; ++k) {
    const double length = distance(corners[k], corners[(k + 1) % 3]);
    if (length > longestLength) {
      longestLength = length;
      longest = k;
    }
  }
  const double area = norm(cross(corners[1] - corners[0], corners[2] - corners[0])) / 2;
  // The even grid of n steps has (n + 1) (n + 2) / 2 points.
  const double mostSteps = std::max(1.0, std::floor((std::sqrt(8.0 * static_cast<double>(maxPoints) + 1) - 3) / 2));
  std::vector<Weights> points;
  if (!(longestLength * longestLength > kNeedleLengthSquaredPerArea * area) || !(longestLength > spacing)) {
    const size_t n = stepsOver(longestLength, spacing, mostSteps);
    for (size_t a = 0; a <= n; ++a)
      for (size_t b = 0; a + b <= n; ++b) points.push_back({double(a) / n, double(b) / n});
    return points;
  }
  const Weights& a = weightOf[longest];
  const Weights& b = weightOf[(longest + 1) % 3];
  const Weights& apex = weightOf[(longest + 2) % 3];
  const double height = 2 * area / longestLength;
  const size_t rows = stepsOver(height, kRowsApartPerSpacing * spacing, mostSteps);
  const size_t mostAlong = std::max<size_t>(1, maxPoints / (rows + 1));
  for (size_t r = 0; r < rows; ++r) {
    const double up = double(r) / rows;  // from the longest edge (0) to the apex (1)
    const size_t n = stepsOver((1 - up) * longestLength, kAlongRowPerSpacing * spacing, double(mostAlong));
    for (size_t k = 0; k <= n; ++k) {
      const double along = double(k) / n;
      const double wa = (1 - up) * (1 - along), wb = (1 - up) * along;
      points.push_back({wa * a[0] + wb * b[0] + up * apex[0], wa * a[1] + wb * b[1] + up * apex[1]});
    }
  }
  points.push_back(apex);
  return points;
}

}  // namespace oraclemesh
