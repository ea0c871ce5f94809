#include "improve/VertexInsertion.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "mesh/Quality.h"

namespace oraclemesh {
namespace {

constexpr double kWorst = -std::numeric_limits<double>::infinity();
// Stands for the new vertex in the star's tets until it has an index.
constexpr int64_t kNewVertex = -1;

std::optional<Point3> circumcentre(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  const std::optional<Point3> offset = circumcentreFromA(a, b, c, d);
  if (!offset) return std::nullopt;
  return a + *offset;
}

std::array<int64_t, 3> faceOpposite(const TetCorners& c, int i) {
  std::array<int64_t, 3> f;
  for (int k = 0, j = 0; k < 4; ++k)
    if (k != i) f[j++] = c[k];
  return f;
}

// The new vertex's star for one candidate point.
class Star {
 public:
  Star(const ImprovementMesh& mesh, int material, const Point3& point)
      : mesh_(mesh), p_(mesh.points()), material_(material), point_(point) {}

  // Builds the cavity from tet `start` and the star over it; false when either is not allowed.
  bool build(int64_t start) {
    const int64_t first = locate(start);
    if (first < 0) return false;
    cavity_ = {first};
    for (size_t k = 0; k < cavity_.size(); ++k) {
      const TetCorners c = mesh_.tet(cavity_[k]);
      for (int i = 0; i < 4; ++i) {
        const auto f = faceOpposite(c, i);
        if (mesh_.isProtectedFace(f[0], f[1], f[2])) continue;
        for (int64_t n : mesh_.tetsWithFace(f[0], f[1], f[2])) {
          if (inCavity(n) || mesh_.material(n) != material_ || !inCircumsphere(n)) continue;
          if (static_cast<int>(cavity_.size()) >= kMaxInsertionCavity) return false;
          cavity_.push_back(n);
        }
      }
    }
    return makeStar();
  }

  // The star's smallest dihedral angle under `bound` (kWorst: a new tet it does not admit).
  double quality(const SizeBound& bound) const {
    double worst = std::numeric_limits<double>::infinity();
    for (const TetCorners& t : made_) {
      const Point3 &a = at(t[0]), &b = at(t[1]), &c = at(t[2]), &d = at(t[3]);
      if (!bound.admits(material_, a, b, c, d)) return kWorst;
      worst = std::min(worst, smallestDihedral(a, b, c, d));
    }
    return worst;
  }

  const std::vector<int64_t>& cavity() const { return cavity_; }
  const std::vector<TetCorners>& made() const { return made_; }
  const Point3& point() const { return point_; }

 private:
  const Point3& at(int64_t v) const { return v == kNewVertex ? point_ : p_[v]; }
  bool inCavity(int64_t t) const { return std::find(cavity_.begin(), cavity_.end(), t) != cavity_.end(); }

  bool inCircumsphere(int64_t t) const {
    const TetCorners& c = mesh_.tet(t);
    const auto centre = circumcentre(p_[c[0]], p_[c[1]], p_[c[2]], p_[c[3]]);
    return centre && distance(point_, *centre) < distance(p_[c[0]], *centre);
  }

  // The tet of the material holding the point, walking from `start` towards it; -1 when the
  // walk would cross a protected face or another material, or takes too long.
  int64_t locate(int64_t start) const {
    int64_t t = start;
    for (int step = 0; step < 32; ++step) {
      const TetCorners& c = mesh_.tet(t);
      int outside = -1;
      for (int i = 0; i < 4 && outside < 0; ++i) {
        TetCorners moved = c;
        moved[i] = kNewVertex;
        if (exactOrientation(at(moved[0]), at(moved[1]), at(moved[2]), at(moved[3])) < 0) outside = i;
      }
      if (outside < 0) return t;
      const auto f = faceOpposite(c, outside);
      if (mesh_.isProtectedFace(f[0], f[1], f[2])) return -1;
      int64_t next = -1;
      for (int64_t n : mesh_.tetsWithFace(f[0], f[1], f[2]))
        if (n != t) next = n;
      if (next < 0 || mesh_.material(next) != material_) return -1;
      t = next;
    }
    return -1;
  }

  // One new tet per face on the cavity's boundary: the cavity tet with the new vertex for the
  // corner inside. Refused when a new tet is not positive (the cavity is not star-shaped from
  // the point), a protected face would be inside the cavity, or a vertex or feature edge of
  // the cavity would not be in the star.
  bool makeStar() {
    made_.clear();
    double oldVolume = 0, newVolume = 0;
    for (int64_t t : cavity_) {
      const TetCorners& c = mesh_.tet(t);
      oldVolume += tetVolume(p_, c);
      for (int i = 0; i < 4; ++i) {
        const auto f = faceOpposite(c, i);
        bool inner = false;
        for (int64_t n : mesh_.tetsWithFace(f[0], f[1], f[2])) inner = inner || (n != t && inCavity(n));
        if (inner) {
          if (mesh_.isProtectedFace(f[0], f[1], f[2])) return false;
          continue;
        }
        TetCorners star = c;
        star[i] = kNewVertex;
        if (exactOrientation(at(star[0]), at(star[1]), at(star[2]), at(star[3])) <= 0) return false;
        newVolume += tetVolume(at(star[0]), at(star[1]), at(star[2]), at(star[3]));
        made_.push_back(star);
      }
    }
    // Positive tets over the boundary faces fill the cavity once unless they wind twice.
    if (!(std::abs(newVolume - oldVolume) <= 1e-9 * oldVolume)) return false;
    auto inStar = [&](int64_t a, int64_t b) {
      for (const TetCorners& s : made_)
        if (std::find(s.begin(), s.end(), a) != s.end() && std::find(s.begin(), s.end(), b) != s.end()) return true;
      return false;
    };
    for (int64_t t : cavity_) {
      const TetCorners& c = mesh_.tet(t);
      for (int64_t v : c)
        if (!inStar(v, v)) return false;
      for (const auto& e : kTetEdgeCorners)
        if (mesh_.isProtectedEdge(c[e[0]], c[e[1]]) && !inStar(c[e[0]], c[e[1]])) return false;
    }
    return true;
  }

  const ImprovementMesh& mesh_;
  const std::vector<Point3>& p_;
  int material_;
  Point3 point_;
  std::vector<int64_t> cavity_;
  std::vector<TetCorners> made_;
};

}  // namespace

int64_t insertVertex(ImprovementMesh& mesh, int64_t t, const SizeCriteria& sizes) {
  if (!mesh.alive(t)) return -1;
  const auto& p = mesh.points();
  const TetCorners c = mesh.tet(t);
  const int material = mesh.material(t);
  std::vector<Point3> candidates = {0.25 * (p[c[0]] + p[c[1]] + p[c[2]] + p[c[3]])};
  if (const auto centre = circumcentre(p[c[0]], p[c[1]], p[c[2]], p[c[3]])) candidates.push_back(*centre);
  for (const auto& e : kTetEdgeCorners)
    if (!mesh.isProtectedEdge(c[e[0]], c[e[1]])) candidates.push_back(0.5 * (p[c[e[0]]] + p[c[e[1]]]));

  std::optional<Star> best;
  double bestQuality = kWorst;
  for (const Point3& point : candidates) {
    Star star(mesh, material, point);
    if (!star.build(t)) continue;
    SizeBound bound;
    bound.criteria = &sizes;
    double before = std::numeric_limits<double>::infinity();
    for (int64_t old : star.cavity()) {
      const TetCorners& k = mesh.tet(old);
      bound.include(tetSize(p[k[0]], p[k[1]], p[k[2]], p[k[3]]));
      before = std::min(before, mesh.quality(old));
    }
    const double after = star.quality(bound);
    if (after > before && after > bestQuality) {
      bestQuality = after;
      best.emplace(std::move(star));
    }
  }
  if (!best) return -1;
  const int64_t v = mesh.addVertex(best->point());
  std::vector<TetCorners> made = best->made();
  for (TetCorners& s : made)
    for (int64_t& w : s)
      if (w == kNewVertex) w = v;
  mesh.replace(best->cavity(), made, material);
  return v;
}

}  // namespace oraclemesh
