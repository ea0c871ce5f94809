#pragma once
// The crossing search's box tests (internal to domain/brep): a segment against grown boxes,
// and a bounding volume hierarchy over the proxy triangles' grown boxes.
#include <CGAL/Bbox_3.h>

#include <gp_XYZ.hxx>

#include <algorithm>
#include <utility>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

// Whether the segment a + t d, t in [0, 1], meets a box grown by a margin on every side (a
// slab test). Growing the box by the margin contains the ball of that radius around it, so
// this never rejects a box within the margin of the segment. The reciprocal direction is
// computed once per segment: the test runs for every AABB node the segment passes.
class SegmentBoxTest {
 public:
  SegmentBoxTest(const Point3& a, const Point3& d) : a_(a) {
    for (int i = 0; i < 3; ++i) inverse_[i] = d[i] != 0.0 ? 1.0 / d[i] : 0.0;
    for (int i = 0; i < 3; ++i) parallel_[i] = d[i] == 0.0;
  }
  bool meets(const CGAL::Bbox_3& box, double margin) const {
    double t0, t1;
    return meets(box, margin, t0, t1);
  }
  // Also gives the part [t0, t1] of the segment inside the grown box.
  bool meets(const CGAL::Bbox_3& box, double margin, double& t0, double& t1) const {
    t0 = 0.0;
    t1 = 1.0;
    for (int i = 0; i < 3; ++i) {
      const double lo = box.min(i) - margin, hi = box.max(i) + margin;
      if (parallel_[i]) {
        if (a_[i] < lo || a_[i] > hi) return false;
        continue;
      }
      double ta = (lo - a_[i]) * inverse_[i], tb = (hi - a_[i]) * inverse_[i];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (t0 > t1) return false;
    }
    return true;
  }

 private:
  Point3 a_, inverse_;
  bool parallel_[3];
};

// A bounding volume hierarchy over boxes (proxy triangles' boxes grown by their face's
// crossing band): which boxes a segment passes through, which boxes hold a point. Built once,
// then only read, so queries may run in parallel.
class BoxTree {
 public:
  void build(std::vector<CGAL::Bbox_3> boxes, std::vector<int> items) {
    boxes_ = std::move(boxes);
    items_ = std::move(items);
    nodes_.clear();
    if (items_.empty()) return;
    nodes_.emplace_back();
    split(0, 0, static_cast<int>(items_.size()));
  }
  bool empty() const { return nodes_.empty(); }
  const CGAL::Bbox_3& box() const { return nodes_.front().box; }
  // visit(item, t0, t1) for every box the segment meets, [t0, t1] its part of the segment.
  template <class Visit>
  void onSegment(const SegmentBoxTest& segment, Visit&& visit) const {
    double t0, t1;
    descend([&](const CGAL::Bbox_3& box) { return segment.meets(box, 0.0, t0, t1); },
            [&](int i) {
              if (segment.meets(boxes_[i], 0.0, t0, t1)) visit(items_[i], t0, t1);
            });
  }
  // visit(item) for every box holding p.
  template <class Visit>
  void atPoint(const gp_XYZ& p, Visit&& visit) const {
    descend([&](const CGAL::Bbox_3& box) { return holds(box, p); },
            [&](int i) {
              if (holds(boxes_[i], p)) visit(items_[i]);
            });
  }

 private:
  // Depth first through the nodes whose box `enters` accepts; atLeaf(i) for every box index
  // of the leaves reached (the caller tests the item's own box).
  template <class Enters, class AtLeaf>
  void descend(Enters&& enters, AtLeaf&& atLeaf) const {
    if (nodes_.empty()) return;
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!enters(node.box)) continue;
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) atLeaf(i);
      } else {
        stack[top++] = node.first;
        stack[top++] = node.first + 1;
      }
    }
  }

  struct Node {
    CGAL::Bbox_3 box;
    int first = 0;  // leaf: first box; inner node: index of the first of its two children
    int count = 0;  // boxes of a leaf, 0 for an inner node
  };
  static bool holds(const CGAL::Bbox_3& b, const gp_XYZ& p) {
    return p.X() >= b.xmin() && p.X() <= b.xmax() && p.Y() >= b.ymin() && p.Y() <= b.ymax() && p.Z() >= b.zmin() &&
           p.Z() <= b.zmax();
  }
  // Makes node `index` the root of boxes [begin, end): halves them at the median of the box
  // centres along the widest axis (depth ~ log2 n, far below the stack size). The two
  // children of a node are stored next to each other, so a node needs only the first index.
  void split(int index, int begin, int end) {
    CGAL::Bbox_3 box = boxes_[begin];
    for (int i = begin + 1; i < end; ++i) box += boxes_[i];
    nodes_[index].box = box;
    if (end - begin <= 4) {
      nodes_[index].first = begin;
      nodes_[index].count = end - begin;
      return;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (box.max(k) - box.min(k) > box.max(axis) - box.min(axis)) axis = k;
    std::vector<int> order(end - begin);
    for (int i = begin; i < end; ++i) order[i - begin] = i;
    const int middle = (end - begin) / 2;
    std::nth_element(order.begin(), order.begin() + middle, order.end(), [&](int x, int y) {
      return boxes_[x].min(axis) + boxes_[x].max(axis) < boxes_[y].min(axis) + boxes_[y].max(axis);
    });
    std::vector<CGAL::Bbox_3> sortedBoxes;
    std::vector<int> sortedItems;
    for (int i : order) {
      sortedBoxes.push_back(boxes_[i]);
      sortedItems.push_back(items_[i]);
    }
    std::copy(sortedBoxes.begin(), sortedBoxes.end(), boxes_.begin() + begin);
    std::copy(sortedItems.begin(), sortedItems.end(), items_.begin() + begin);
    const int children = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[index].first = children;
    nodes_[index].count = 0;
    split(children, begin, begin + middle);
    split(children + 1, begin + middle, end);
  }
  std::vector<CGAL::Bbox_3> boxes_;
  std::vector<int> items_;
  std::vector<Node> nodes_;
};

}  // namespace oraclemesh
