#include "sizing/SizeField.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "Error.h"
#include "sizing/ConeTree.h"
#include "sizing/SampleThinning.h"

namespace oraclemesh {

const char* sizeReasonName(SizeReason reason) {
  switch (reason) {
    case SizeReason::Curvature: return "curvature";
    case SizeReason::ShortEdge: return "short_edge";
    case SizeReason::Thickness: return "thickness";
    case SizeReason::Gap: return "gap";
  }
  return "?";
}

struct SizeField::Impl {
  double grading = 0, cap = 0, floor = 0;
  ConeTree tree;
  size_t counts[kSizeReasonCount] = {};
  size_t total = 0, taken = 0;
  SizeSample smallest;
};

SizeField::SizeField(std::vector<SizeSample> samples, double grading, double cap, double floor, double thinning)
    : impl_(std::make_unique<Impl>()) {
  if (!(grading > 0) || !std::isfinite(grading))
    throw InputError("the size grading must be a positive number, got " + std::to_string(grading));
  Impl& m = *impl_;
  m.grading = grading;
  m.cap = cap;
  m.floor = std::min(floor, cap);
  m.smallest.size = cap;
  std::vector<SizeSample> kept;
  for (SizeSample& s : samples) {
    if (!std::isfinite(s.size) || !(s.size < cap) || !isFinite(s.point)) continue;
    s.size = std::max(s.size, m.floor);
    if (s.size < m.smallest.size) m.smallest = s;
    kept.push_back(s);
  }
  m.taken = kept.size();
  if (thinning > 0) kept = thinSizeSamples(std::move(kept), grading, thinning);
  m.total = kept.size();
  for (const SizeSample& s : kept) ++m.counts[static_cast<int>(s.reason)];
  if (kept.empty()) return;
  std::vector<Point3> points;
  std::vector<double> sizes;
  for (const SizeSample& s : kept) {
    points.push_back(s.point);
    sizes.push_back(s.size);
  }
  m.tree = ConeTree(points, sizes, grading);
}

SizeField::~SizeField() = default;

double SizeField::at(const Point3& p) const { return impl_->tree.minimum(p, impl_->cap); }

double SizeField::grading() const { return impl_->grading; }
double SizeField::cap() const { return impl_->cap; }
double SizeField::floor() const { return impl_->floor; }
size_t SizeField::sampleCount() const { return impl_->total; }
size_t SizeField::samplesTaken() const { return impl_->taken; }
size_t SizeField::sampleCount(SizeReason reason) const { return impl_->counts[static_cast<int>(reason)]; }
double SizeField::smallestSize() const { return impl_->smallest.size; }
Point3 SizeField::smallestAt() const { return impl_->smallest.point; }
SizeReason SizeField::smallestReason() const { return impl_->smallest.reason; }

}  // namespace oraclemesh
