#pragma once
// The first triangle of an AABB tree that a ray meets within a given reach. CGAL's
// first_intersection follows the ray to the end of the model; the sizing's rays only care
// what they meet within the distance at which a wall or a gap still asks for less than the
// largest size, and a ray leaving an assembly's outside or crossing a thick part would
// otherwise open every box along its whole way.
//
// Every hit nearer than the reach is the one CGAL's query gives: boxes are opened nearest
// entry first, ties in the order CGAL opens them, each triangle is intersected by the
// tree's own intersection object, and the nearest by the ray parameter along the direction's
// largest coordinate wins (a segment, where the ray runs within a triangle, by its nearer
// end; of equal parameters, the first found). Before the exact intersection, whose
// predicates fall back to multi-precision arithmetic next to a ray's start, plain floating
// point leaves out the triangles it proves missed or met beyond the best hit so far.
#include <CGAL/AABB_tree.h>

#include <boost/heap/priority_queue.hpp>
#include <boost/optional.hpp>
#include <boost/variant.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <utility>

namespace oraclemesh {

template <class Tree>
class RayFirstHit {
 public:
  using Traits = typename Tree::AABB_traits;
  using Kernel = typename Traits::Geom_traits;
  using Ray = typename Kernel::Ray_3;
  using Hit = typename Tree::template Intersection_and_primitive_id<Ray>::Type;

  RayFirstHit(const Tree& tree, const Ray& ray, double reach) : tree_(tree), ray_(ray), best_(reach) {
    const typename Kernel::Point_3 s = ray.source();
    const typename Kernel::Vector_3 d = ray.to_vector();
    for (int i = 0; i < 3; ++i) {
      source_[i] = s[i];
      direction_[i] = d[i];
      if (std::abs(d[i]) > std::abs(d[axis_])) axis_ = i;
    }
    search();
  }

  // The first hit at a parameter below the reach (for a unit direction, a distance).
  const boost::optional<Hit>& hit() const { return hit_; }

 private:
  using Node = CGAL::AABB_node<Traits>;
  using Primitive = typename Tree::Primitive;

  struct Pending {
    const Node* node;
    double entry;
    std::size_t primitives;  // under the node: its layout in CGAL's tree
    bool operator>(const Pending& other) const { return entry > other.entry; }
  };

  void search() {
    if (tree_.size() < 2) {  // no inner node to walk: CGAL's own query
      hit_ = tree_.first_intersection(ray_);
      if (hit_ && !(boost::apply_visitor(ParameterOf{this}, hit_->first) < best_)) hit_ = boost::none;
      return;
    }
    const auto entryOf = tree_.traits().intersection_distance_object();
    boost::heap::priority_queue<Pending, boost::heap::compare<std::greater<Pending>>> open;
    open.push({tree_.root_node(), 0, tree_.size()});
    auto push = [&](const Node& child, std::size_t primitives) {
      const boost::optional<double> entry = entryOf(ray_, child.bbox());
      if (entry) open.push({&child, *entry, primitives});
    };
    while (!open.empty() && open.top().entry < best_) {
      const Pending current = open.top();
      open.pop();
      const Node& n = *current.node;
      if (current.primitives == 2) {
        consider(n.left_data());
        consider(n.right_data());
      } else if (current.primitives == 3) {
        consider(n.left_data());
        push(n.right_child(), 2);
      } else {
        push(n.left_child(), current.primitives / 2);
        push(n.right_child(), current.primitives - current.primitives / 2);
      }
    }
  }

  void consider(const Primitive& primitive) {
    if (missesBeforeBest(primitive.datum())) return;
    boost::optional<Hit> met = tree_.traits().intersection_object()(ray_, primitive);
    if (!met) return;
    const double t = boost::apply_visitor(ParameterOf{this}, met->first);
    if (t < best_) {
      best_ = t;
      hit_ = std::move(met);
    }
  }

  struct ParameterOf {
    const RayFirstHit* self;
    double operator()(const typename Kernel::Point_3& p) const { return self->parameter(p); }
    double operator()(const typename Kernel::Segment_3& s) const {
      return std::min(self->parameter(s.source()), self->parameter(s.target()));
    }
  };
  double parameter(const typename Kernel::Point_3& p) const { return (p[axis_] - source_[axis_]) / direction_[axis_]; }

  // Whether plain floating point proves that the ray misses the triangle, or meets it only at
  // or beyond the best hit so far (its plane, then Moller-Trumbore; each quantity with an
  // error bound hundreds of times its rounding). Rays through its edges, starting next to it
  // or running within its plane go to the exact intersection.
  bool missesBeforeBest(const typename Kernel::Triangle_3& triangle) const {
    double a[3], e1[3], e2[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = triangle[0][i];
      e1[i] = triangle[1][i] - a[i];
      e2[i] = triangle[2][i] - a[i];
    }
    const double* d = direction_;
    const double s[3] = {source_[0] - a[0], source_[1] - a[1], source_[2] - a[2]};
    const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
    const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    const double lengthD = length(d), lengthE1 = length(e1), lengthE2 = length(e2), lengthS = length(s);
    // The best hit's parameter comes from a constructed point, rounded relative to the
    // coordinates themselves: a triangle met as near is never left out.
    double magnitude = 0;
    for (int i = 0; i < 3; ++i) magnitude = std::max({magnitude, std::abs(source_[i]), std::abs(a[i])});
    const double best = best_ + kErrorPerRounding * magnitude / std::abs(direction_[axis_]);
    // The triangle's plane beyond the best hit: at height h above it and sinking at rate
    // |d . n| (= |det| / |n|), the ray reaches it no sooner than h / rate. Rays parallel to
    // the triangle (the side faces of an axis-aligned part) end here.
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double lengthN = length(n);
    if (!(lengthN > 0)) return false;
    const double height = std::abs(s[0] * n[0] + s[1] * n[1] + s[2] * n[2]) / lengthN;
    const double rate = std::abs(det) / lengthN;
    const double perLengthN = kErrorPerRounding * lengthE1 * lengthE2 / lengthN;
    if (height - perLengthN * lengthS > best * (rate + perLengthN * lengthD)) return true;
    if (!(std::abs(det) > 1e-9 * lengthD * lengthE1 * lengthE2)) return false;
    const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
    const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    const double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    const double scale = kErrorPerRounding / std::abs(det);
    const double slackU = scale * lengthS * lengthD * lengthE2, slackV = scale * lengthD * lengthS * lengthE1;
    const double slackT = scale * lengthE2 * lengthS * lengthE1;
    return u < -slackU || v < -slackV || u + v > 1 + slackU + slackV || t < -slackT || t - slackT > best;
  }
  static double length(const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
  // Relative error allowed per product of three lengths: a dot of a cross product rounds to a
  // few units of 1.1e-16.
  static constexpr double kErrorPerRounding = 1e-12;

  const Tree& tree_;
  Ray ray_;
  double source_[3] = {0, 0, 0}, direction_[3] = {0, 0, 0};
  int axis_ = 0;
  double best_;
  boost::optional<Hit> hit_;
};

}  // namespace oraclemesh
