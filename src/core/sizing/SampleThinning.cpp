#include "sizing/SampleThinning.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace oraclemesh {

namespace {

// A grid cell of one size level: level l has cells of side smallest * 2^l.
struct CellKey {
  int64_t level, x, y, z;
  bool operator==(const CellKey& o) const { return level == o.level && x == o.x && y == o.y && z == o.z; }
};

struct CellKeyHash {
  size_t operator()(const CellKey& k) const {
    uint64_t h = static_cast<uint64_t>(k.level);
    for (int64_t v : {k.x, k.y, k.z}) h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(v);
    return static_cast<size_t>(h ^ (h >> 29));
  }
};

// Levels below the sample's own that are searched too: samples two levels smaller dominate
// from farther than a cell of theirs, so further levels would rarely find more.
constexpr int kLevelsBelow = 2;

}  // namespace

std::vector<SizeSample> thinSizeSamples(std::vector<SizeSample> samples, double grading, double tolerance) {
  std::vector<SizeSample> kept, unusable;
  double smallest = std::numeric_limits<double>::infinity();
  for (const SizeSample& s : samples)
    if (s.size > 0 && std::isfinite(s.size) && isFinite(s.point)) smallest = std::min(smallest, s.size);
  std::vector<size_t> order;
  for (size_t i = 0; i < samples.size(); ++i) {
    const SizeSample& s = samples[i];
    if (s.size > 0 && std::isfinite(s.size) && isFinite(s.point))
      order.push_back(i);
    else
      unusable.push_back(s);  // passed on for the field to judge
  }
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return samples[a].size < samples[b].size; });
  std::unordered_map<CellKey, std::vector<uint32_t>, CellKeyHash> grid;  // kept samples per cell
  auto cellOf = [&](const Point3& p, int64_t level) {
    const double side = smallest * std::ldexp(1.0, static_cast<int>(level));
    return CellKey{level, static_cast<int64_t>(std::floor(p[0] / side)), static_cast<int64_t>(std::floor(p[1] / side)),
                   static_cast<int64_t>(std::floor(p[2] / side))};
  };
  for (size_t i : order) {
    const SizeSample& s = samples[i];
    const int64_t level = static_cast<int64_t>(std::floor(std::log2(s.size / smallest)));
    const double reach = (1 + tolerance) * s.size;
    bool dominated = false;
    for (int64_t l = level; l >= std::max<int64_t>(0, level - kLevelsBelow) && !dominated; --l) {
      const CellKey centre = cellOf(s.point, l);
      for (int64_t dx = -1; dx <= 1 && !dominated; ++dx)
        for (int64_t dy = -1; dy <= 1 && !dominated; ++dy)
          for (int64_t dz = -1; dz <= 1 && !dominated; ++dz) {
            const auto found = grid.find({l, centre.x + dx, centre.y + dy, centre.z + dz});
            if (found == grid.end()) continue;
            for (uint32_t k : found->second)
              if (kept[k].size + grading * distance(kept[k].point, s.point) <= reach) {
                dominated = true;
                break;
              }
          }
    }
    if (dominated) continue;
    grid[cellOf(s.point, level)].push_back(static_cast<uint32_t>(kept.size()));
    kept.push_back(s);
  }
  kept.insert(kept.end(), unusable.begin(), unusable.end());
  return kept;
}

}  // namespace oraclemesh
