#pragma once
// The exact graded minimum over size samples, min_i (h_i + grading |p - x_i|), by branch and
// bound in a kd-tree whose nodes know their box and their smallest size: a node whose smallest
// size plus the graded distance to its box cannot beat the best value found is skipped. Near
// the surfaces a query opens a few leaves; far from them whole subtrees fall at once.
#include <cstdint>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

class ConeTree {
 public:
  ConeTree() = default;
  ConeTree(const std::vector<Point3>& points, const std::vector<double>& sizes, double grading);

  // min(bound, min_i size_i + grading |p - x_i|); `bound` when there are no samples.
  double minimum(const Point3& p, double bound) const;
  bool empty() const { return nodes_.empty(); }

 private:
  struct Node {
    Bbox box;
    double smallest = 0;
    uint32_t begin = 0, end = 0;  // samples [begin, end) in tree order
    int32_t left = -1, right = -1;  // children (both or neither)
  };
  int32_t build(uint32_t begin, uint32_t end, std::vector<uint32_t>& order, const std::vector<Point3>& points);
  double lowerBound(const Node& n, const Point3& p) const;

  static constexpr uint32_t kLeafSize = 8;
  double grading_ = 0;
  std::vector<Point3> points_;  // in tree order, so a leaf's samples lie together in memory
  std::vector<double> sizes_;
  std::vector<Node> nodes_;
};

}  // namespace oraclemesh
