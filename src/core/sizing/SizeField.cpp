#include "sizing/SizeField.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_incremental_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>
#include <boost/iterator/counting_iterator.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>

#include "Error.h"

namespace oraclemesh {

const char* sizeReasonName(SizeReason reason) {
  switch (reason) {
    case SizeReason::Curvature: return "curvature";
    case SizeReason::ShortEdge: return "short_edge";
    case SizeReason::Thickness: return "thickness";
  }
  return "?";
}

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using PointMap = CGAL::Pointer_property_map<K::Point_3>::const_type;
using BaseTraits = CGAL::Search_traits_3<K>;
using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, BaseTraits>;
using Distance = CGAL::Distance_adapter<std::size_t, PointMap, CGAL::Euclidean_distance<BaseTraits>>;
using Search = CGAL::Orthogonal_incremental_neighbor_search<Traits, Distance>;
using Tree = Search::Tree;

// Samples whose sizes lie within a factor 2 of each other. A query walks each level's samples
// nearest first and stops once the level's smallest size plus the graded distance cannot beat
// the best value found: exact, and short because sizes within a level are alike.
struct Level {
  double smallest = 0;
  std::vector<K::Point_3> points;
  std::vector<double> sizes;
  std::unique_ptr<Tree> tree;
};

constexpr double kLevelRatio = 2;

}  // namespace

// A cell of the lazy octree: the exact field at its centre, and its children once a query
// needed them (8 consecutive nodes from firstChild).
struct OctreeNode {
  double centreValue = 0;
  int64_t firstChild = -1;
};

struct SizeField::Impl {
  double grading = 0, cap = 0, floor = 0;
  std::vector<Level> levels;
  size_t counts[kSizeReasonCount] = {};
  size_t total = 0;
  SizeSample smallest;
  // The octree over the domain's bounding cube.
  Point3 rootCentre{};
  double rootHalf = 0;
  std::vector<OctreeNode> nodes;
  std::mutex mutex;

  double exact(const Point3& p) const;
  // A cell is fine enough when the field varies by less than kTolerance of its centre value
  // across it (Lipschitz: at most grading * half diagonal), or when it is far below the floor.
  bool fineEnough(const OctreeNode& n, double half) const {
    return grading * std::sqrt(3.0) * half <= kTolerance * n.centreValue || half < 0.25 * floor;
  }
};

SizeField::SizeField(std::vector<SizeSample> samples, double grading, double cap, double floor, const Bbox& domain)
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
    if (!std::isfinite(s.size) || !(s.size < cap)) continue;
    s.size = std::max(s.size, m.floor);
    ++m.counts[static_cast<int>(s.reason)];
    if (s.size < m.smallest.size) m.smallest = s;
    kept.push_back(s);
  }
  m.total = kept.size();
  if (kept.empty()) return;
  const double smallest = m.smallest.size;
  const int levelCount = 1 + static_cast<int>(std::floor(std::log(cap / smallest) / std::log(kLevelRatio)));
  m.levels.resize(std::max(levelCount, 1));
  for (size_t l = 0; l < m.levels.size(); ++l) m.levels[l].smallest = smallest * std::pow(kLevelRatio, double(l));
  for (const SizeSample& s : kept) {
    const int l = std::clamp(static_cast<int>(std::floor(std::log(s.size / smallest) / std::log(kLevelRatio))), 0,
                             static_cast<int>(m.levels.size()) - 1);
    m.levels[l].points.emplace_back(s.point[0], s.point[1], s.point[2]);
    m.levels[l].sizes.push_back(s.size);
    m.levels[l].smallest = std::min(m.levels[l].smallest, s.size);
  }
  for (Level& level : m.levels) {
    if (level.points.empty()) continue;
    const PointMap map(level.points.data());
    level.tree = std::make_unique<Tree>(boost::counting_iterator<std::size_t>(0),
                                        boost::counting_iterator<std::size_t>(level.points.size()),
                                        Tree::Splitter(), Traits(map));
    level.tree->build();  // now, so that queries only read the tree
  }
  Bbox box = domain;
  for (const SizeSample& s : kept) box.add(s.point);
  m.rootCentre = 0.5 * (box.min + box.max);
  for (int i = 0; i < 3; ++i) m.rootHalf = std::max(m.rootHalf, 0.5 * (box.max[i] - box.min[i]));
  m.rootHalf *= 1.01;
  m.nodes.push_back({m.exact(m.rootCentre), -1});
}

SizeField::~SizeField() = default;

double SizeField::exactAt(const Point3& p) const { return impl_->exact(p); }

double SizeField::at(const Point3& p) const {
  Impl& m = *impl_;
  if (m.levels.empty()) return m.cap;
  for (int i = 0; i < 3; ++i)
    if (!(std::abs(p[i] - m.rootCentre[i]) <= m.rootHalf)) return m.exact(p);  // also NaN
  std::lock_guard<std::mutex> lock(m.mutex);
  int64_t node = 0;
  Point3 centre = m.rootCentre;
  double half = m.rootHalf;
  while (true) {
    if (m.nodes[node].firstChild < 0) {
      if (m.fineEnough(m.nodes[node], half)) return m.nodes[node].centreValue;
      const int64_t first = static_cast<int64_t>(m.nodes.size());
      for (int octant = 0; octant < 8; ++octant) {
        Point3 c = centre;
        for (int i = 0; i < 3; ++i) c[i] += (octant >> i & 1 ? 0.5 : -0.5) * half;
        m.nodes.push_back({m.exact(c), -1});
      }
      m.nodes[node].firstChild = first;
    }
    int octant = 0;
    for (int i = 0; i < 3; ++i)
      if (p[i] >= centre[i]) octant |= 1 << i;
    half *= 0.5;
    for (int i = 0; i < 3; ++i) centre[i] += (octant >> i & 1 ? 1 : -1) * half;
    node = m.nodes[node].firstChild + octant;
  }
}

double SizeField::Impl::exact(const Point3& p) const {
  const Impl& m = *this;
  double best = m.cap;
  const K::Point_3 query(p[0], p[1], p[2]);
  for (const Level& level : m.levels) {
    if (!level.tree || level.smallest >= best) continue;
    const PointMap map(level.points.data());
    Search search(*level.tree, query, 0.0, true, Distance(map));
    for (auto it = search.begin(); it != search.end(); ++it) {
      const double d = std::sqrt(it->second);
      if (level.smallest + m.grading * d >= best) break;
      best = std::min(best, level.sizes[it->first] + m.grading * d);
    }
  }
  return best;
}

double SizeField::grading() const { return impl_->grading; }
double SizeField::cap() const { return impl_->cap; }
double SizeField::floor() const { return impl_->floor; }
size_t SizeField::sampleCount() const { return impl_->total; }
size_t SizeField::sampleCount(SizeReason reason) const { return impl_->counts[static_cast<int>(reason)]; }
double SizeField::smallestSize() const { return impl_->smallest.size; }
Point3 SizeField::smallestAt() const { return impl_->smallest.point; }
SizeReason SizeField::smallestReason() const { return impl_->smallest.reason; }

}  // namespace oraclemesh
