// The sizing's ray query (sizing/RayFirstHit.h) against CGAL's first_intersection on the same
// tree: the same triangle and point for every hit within the reach, and none beyond it. The
// rays start on the triangles, at their corners and edge midpoints, and run along axes through
// the boxes' shared edges and parallel to their faces, where the floating-point prefilter must
// hand over to the exact test and equal parameters must keep CGAL's choice.
#include <gtest/gtest.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <random>
#include <vector>

#include "sizing/RayFirstHit.h"
#include "discrete_shapes.h"

namespace oraclemesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<K::Triangle_3>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>>>;

void append(Triangles& out, const test::Triangles& shape) {
  for (const auto& t : shape.triangles) {
    const Point3 &a = shape.points[t[0]], &b = shape.points[t[1]], &c = shape.points[t[2]];
    out.emplace_back(K::Point_3(a[0], a[1], a[2]), K::Point_3(b[0], b[1], b[2]), K::Point_3(c[0], c[1], c[2]));
  }
}

// Two cylinders, one through the other, and a row of boxes that touch face to face (1e-6
// apart, and shifted, for the last pair): shared edges, coplanar faces and near contacts.
Triangles scene() {
  Triangles out;
  append(out, test::tessellatedCylinder({0, 0, 0}, 5, 20, 48));
  append(out, test::tessellatedCylinder({0, 0, 5}, 2, 20, 17));
  for (int k = 0; k < 4; ++k) append(out, test::triangleBox({10.0 + 4 * k, -2, 0}, 4, 4, 4));
  append(out, test::triangleBox({26 + 1e-6, -1.7, 0.3}, 4, 4, 4));
  return out;
}

double parameter(const K::Ray_3& ray, const K::Point_3& p) {
  const K::Vector_3 d = ray.to_vector();
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(d[i]) > std::abs(d[axis])) axis = i;
  return (p[axis] - ray.source()[axis]) / d[axis];
}

std::vector<K::Ray_3> rays(const Triangles& triangles) {
  std::vector<K::Ray_3> out;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (const K::Triangle_3& t : triangles) {
    const K::Vector_3 n = CGAL::unit_normal(t[0], t[1], t[2]);
    const std::vector<K::Point_3> starts = {CGAL::centroid(t), t[0], CGAL::midpoint(t[0], t[1])};
    for (const K::Point_3& p : starts) {
      const K::Point_3 outside = p + 1e-7 * n, inside = p - 1e-7 * n;
      out.emplace_back(outside, n);
      out.emplace_back(inside, -n);
      out.emplace_back(p, K::Vector_3(unit(rng), unit(rng), unit(rng)));
    }
  }
  // Along the axes through the boxes' edges and diagonals' ends.
  for (double y : {-2.0, 0.0, 2.0})
    for (double z : {0.0, 2.0, 4.0}) {
      out.emplace_back(K::Point_3(-30, y, z), K::Vector_3(1, 0, 0));
      out.emplace_back(K::Point_3(12, y, z + 9), K::Vector_3(0, 0, -1));
    }
  return out;
}

TEST(RayFirstHit, GivesCgalsFirstHitWithinItsReachAndNoneBeyond) {
  const Triangles triangles = scene();
  const Tree tree(triangles.cbegin(), triangles.cend());
  int hits = 0, beyond = 0;
  for (const K::Ray_3& ray : rays(triangles)) {
    const auto expected = tree.first_intersection(ray);
    for (double reach : {1e300, 3.0}) {
      const RayFirstHit<Tree> search(tree, ray, reach);
      const auto& hit = search.hit();
      const K::Point_3* point = expected ? boost::get<K::Point_3>(&expected->first) : nullptr;
      const bool within = point && parameter(ray, *point) < reach;
      if (!expected || (point && !within)) {
        beyond += expected.has_value();
        EXPECT_FALSE(hit) << "ray from " << ray.source() << " along " << ray.to_vector() << ", reach " << reach;
        continue;
      }
      if (!point) continue;  // the ray runs within a triangle: its segment's nearer end decides, as below
      ASSERT_TRUE(hit) << "ray from " << ray.source() << " along " << ray.to_vector() << ", reach " << reach;
      EXPECT_EQ(hit->second, expected->second) << "ray from " << ray.source() << " along " << ray.to_vector();
      const K::Point_3* found = boost::get<K::Point_3>(&hit->first);
      ASSERT_NE(found, nullptr);
      EXPECT_EQ(*found, *point);
      ++hits;
    }
  }
  std::cout << "[ figures  ] " << hits << " hits compared, " << beyond << " beyond the reach or none\n";
  EXPECT_GT(hits, 1000);
  EXPECT_GT(beyond, 100);
}

}  // namespace
}  // namespace oraclemesh
