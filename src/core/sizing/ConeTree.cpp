#include "sizing/ConeTree.h"

#include <algorithm>
#include <numeric>

namespace oraclemesh {

ConeTree::ConeTree(const std::vector<Point3>& points, const std::vector<double>& sizes, double grading)
    : grading_(grading) {
  if (points.empty()) return;
  std::vector<uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  nodes_.reserve(2 * points.size() / kLeafSize + 2);
  build(0, static_cast<uint32_t>(points.size()), order, points);
  points_.reserve(points.size());
  sizes_.reserve(points.size());
  for (uint32_t i : order) {
    points_.push_back(points[i]);
    sizes_.push_back(sizes[i]);
  }
  for (Node& n : nodes_) {
    n.smallest = sizes_[n.begin];
    for (uint32_t i = n.begin; i < n.end; ++i) n.smallest = std::min(n.smallest, sizes_[i]);
  }
}

// Splits at the median of the box's longest side; ties in the coordinate are broken by the
// sample's index, so the tree (and with it nothing but speed) depends only on the samples.
int32_t ConeTree::build(uint32_t begin, uint32_t end, std::vector<uint32_t>& order, const std::vector<Point3>& points) {
  const int32_t index = static_cast<int32_t>(nodes_.size());
  nodes_.emplace_back();
  Bbox box;
  for (uint32_t i = begin; i < end; ++i) box.add(points[order[i]]);
  nodes_[index].box = box;
  nodes_[index].begin = begin;
  nodes_[index].end = end;
  if (end - begin <= kLeafSize) return index;
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (box.max[a] - box.min[a] > box.max[axis] - box.min[axis]) axis = a;
  const uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end, [&](uint32_t a, uint32_t b) {
    return points[a][axis] < points[b][axis] || (points[a][axis] == points[b][axis] && a < b);
  });
  const int32_t left = build(begin, middle, order, points);
  const int32_t right = build(middle, end, order, points);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

double ConeTree::lowerBound(const Node& n, const Point3& p) const {
  double squared = 0;
  for (int i = 0; i < 3; ++i) {
    const double below = n.box.min[i] - p[i], above = p[i] - n.box.max[i];
    const double out = std::max({below, above, 0.0});
    squared += out * out;
  }
  return n.smallest + grading_ * std::sqrt(squared);
}

double ConeTree::minimum(const Point3& p, double bound) const {
  if (nodes_.empty()) return bound;
  double best = bound;
  // Depth-first, nearer child first; a tree of 2^32 samples is 29 levels of kLeafSize deep.
  struct Pending {
    int32_t node;
    double lower;
  };
  Pending stack[64];
  int top = 0;
  stack[top++] = {0, lowerBound(nodes_[0], p)};
  while (top > 0) {
    const Pending current = stack[--top];
    if (current.lower >= best) continue;
    const Node& n = nodes_[current.node];
    if (n.left < 0) {
      for (uint32_t i = n.begin; i < n.end; ++i) best = std::min(best, sizes_[i] + grading_ * distance(p, points_[i]));
      continue;
    }
    Pending a{n.left, lowerBound(nodes_[n.left], p)}, b{n.right, lowerBound(nodes_[n.right], p)};
    if (a.lower > b.lower) std::swap(a, b);
    if (b.lower < best) stack[top++] = b;
    if (a.lower < best) stack[top++] = a;
  }
  return best;
}

}  // namespace oraclemesh
