#include "sizing/BondedWedges.h"

#include <algorithm>
#include <cmath>

namespace oraclemesh {

BondedWedges::BondedWedges(std::vector<BondedWedgeSample> samples) : samples_(std::move(samples)) {
  for (const BondedWedgeSample& s : samples_) cell_ = std::max(cell_, s.reach);
  if (!(cell_ > 0)) return;
  for (size_t i = 0; i < samples_.size(); ++i) grid_[cellOf(samples_[i].at)].push_back(i);
}

size_t BondedWedges::CellHash::operator()(const CellKey& k) const {
  return std::hash<long long>()(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
}

BondedWedges::CellKey BondedWedges::cellOf(const Point3& p) const {
  return {static_cast<long long>(std::floor(p[0] / cell_)), static_cast<long long>(std::floor(p[1] / cell_)),
          static_cast<long long>(std::floor(p[2] / cell_))};
}

double BondedWedges::widthAt(const Point3& p) const {
  if (grid_.empty() || !isFinite(p)) return 0;
  const CellKey c = cellOf(p);
  double widest = 0;
  for (long long dx = -1; dx <= 1; ++dx)
    for (long long dy = -1; dy <= 1; ++dy)
      for (long long dz = -1; dz <= 1; ++dz) {
        const auto it = grid_.find({c.x + dx, c.y + dy, c.z + dz});
        if (it == grid_.end()) continue;
        for (size_t i : it->second) {
          const BondedWedgeSample& s = samples_[i];
          if (s.width > widest && distance(s.at, p) <= s.reach) widest = s.width;
        }
      }
  return widest;
}

}  // namespace oraclemesh
