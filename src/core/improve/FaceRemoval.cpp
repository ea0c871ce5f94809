#include "improve/FaceRemoval.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace oraclemesh {
namespace {

constexpr double kWorst = -std::numeric_limits<double>::infinity();

// The corner of tet t that is not x, y or z.
int64_t apexOf(const ImprovementMesh& mesh, int64_t t, int64_t x, int64_t y, int64_t z) {
  for (int64_t v : mesh.tet(t))
    if (v != x && v != y && v != z) return v;
  return -1;
}

// A sandwiched face, its corners ordered so that (v0, v1, v2, top) is positive; edge i runs
// from v[i] to v[i+1]. Faces are numbered in the order the search reached them, so a face's
// children come after it.
struct SandwichFace {
  std::array<int64_t, 3> v;
  int64_t top_tet = -1, bottom_tet = -1;
  int entry = -1;                        // the edge shared with the face it was reached from
  std::array<int, 3> child{-1, -1, -1};  // the face reached across each other edge
  std::array<double, 3> rim{};           // the new tet's quality on each edge as a rim edge
  double subtree = kWorst;               // the best disk of this face and faces beyond it
};

class Sandwich {
 public:
  Sandwich(const ImprovementMesh& mesh, int64_t top, int64_t bottom, int material)
      : mesh_(mesh), p_(mesh.points()), top_(top), bottom_(bottom), material_(material) {}

  void search(const SandwichFace& first) {
    faces_ = {first};
    used_ = {top_, bottom_, first.v[0], first.v[1], first.v[2]};
    for (size_t f = 0; f < faces_.size(); ++f)
      for (int i = 0; i < 3; ++i)
        if (i != faces_[f].entry && static_cast<int>(faces_.size()) < kMaxRemovedFaces) reach(static_cast<int>(f), i);
  }

  // The disk whose worst new tet is best under `bound`: its faces and new tets; returns that
  // worst quality (kWorst: none).
  double choose(const SizeBound& bound, std::vector<int>& chosen, std::vector<TetCorners>& made) {
    for (int f = static_cast<int>(faces_.size()) - 1; f >= 0; --f) {
      SandwichFace& face = faces_[f];
      face.subtree = std::numeric_limits<double>::infinity();
      for (int i = 0; i < 3; ++i) {
        if (i == face.entry) continue;
        face.rim[i] = rimQuality(face, i, bound);
        const double beyond = face.child[i] >= 0 ? std::max(face.rim[i], faces_[face.child[i]].subtree) : face.rim[i];
        face.subtree = std::min(face.subtree, beyond);
      }
    }
    chosen.clear();
    made.clear();
    if (faces_[0].subtree == kWorst) return kWorst;
    collect(0, chosen, made);
    return faces_[0].subtree;
  }

  std::vector<int> everyFace() const {
    std::vector<int> all(faces_.size());
    for (size_t f = 0; f < all.size(); ++f) all[f] = static_cast<int>(f);
    return all;
  }

  // The tets removing these faces removes: each face's two.
  std::vector<int64_t> removedBy(const std::vector<int>& chosen) const {
    std::vector<int64_t> old;
    for (int f : chosen) {
      old.push_back(faces_[f].top_tet);
      old.push_back(faces_[f].bottom_tet);
    }
    return old;
  }

 private:
  // The new tet on edge i of a face when that edge is on the disk's rim.
  TetCorners rimTet(const SandwichFace& face, int i) const {
    return {top_, bottom_, face.v[(i + 1) % 3], face.v[i]};
  }

  // The tet other than `known` with face xyz, when there are two.
  int64_t otherTet(int64_t x, int64_t y, int64_t z, int64_t known) const {
    const std::vector<int64_t> tets = mesh_.tetsWithFace(x, y, z);
    if (tets.size() != 2) return -1;
    return tets[0] == known ? tets[1] : tets[0];
  }

  // Adds the sandwiched face across edge i of face f, if there is one the disk may take: its
  // third corner new to the disk (so every corner stays on the rim), the edge and the faces it
  // would remove unprotected, one material, and the face on the same side of both apexes.
  void reach(int f, int i) {
    const int64_t p = faces_[f].v[i], q = faces_[f].v[(i + 1) % 3];
    if (mesh_.isProtectedEdge(p, q) || mesh_.isProtectedFace(top_, p, q) || mesh_.isProtectedFace(bottom_, p, q))
      return;
    const int64_t upper = otherTet(top_, p, q, faces_[f].top_tet);
    const int64_t lower = otherTet(bottom_, p, q, faces_[f].bottom_tet);
    if (upper < 0 || lower < 0 || mesh_.material(upper) != material_ || mesh_.material(lower) != material_) return;
    const int64_t w = apexOf(mesh_, upper, top_, p, q);
    if (w < 0 || apexOf(mesh_, lower, bottom_, p, q) != w) return;
    if (std::find(used_.begin(), used_.end(), w) != used_.end()) return;
    if (mesh_.isProtectedFace(q, p, w)) return;
    if (exactOrientation(p_[q], p_[p], p_[w], p_[top_]) <= 0 || exactOrientation(p_[q], p_[p], p_[w], p_[bottom_]) >= 0)
      return;
    SandwichFace next;
    next.v = {q, p, w};
    next.top_tet = upper;
    next.bottom_tet = lower;
    next.entry = 0;
    faces_[f].child[i] = static_cast<int>(faces_.size());
    faces_.push_back(next);
    used_.push_back(w);
  }

  double rimQuality(const SandwichFace& face, int i, const SizeBound& bound) const {
    const TetCorners t = rimTet(face, i);
    if (exactOrientation(p_[t[0]], p_[t[1]], p_[t[2]], p_[t[3]]) <= 0) return kWorst;
    if (!bound.admits(material_, p_[t[0]], p_[t[1]], p_[t[2]], p_[t[3]])) return kWorst;
    return smallestDihedral(p_, t);
  }

  // A child is taken only when it does better than keeping the edge on the rim.
  void collect(int f, std::vector<int>& chosen, std::vector<TetCorners>& made) const {
    chosen.push_back(f);
    const SandwichFace& face = faces_[f];
    for (int i = 0; i < 3; ++i) {
      if (i == face.entry) continue;
      if (face.child[i] >= 0 && faces_[face.child[i]].subtree > face.rim[i])
        collect(face.child[i], chosen, made);
      else
        made.push_back(rimTet(face, i));
    }
  }

  const ImprovementMesh& mesh_;
  const std::vector<Point3>& p_;
  int64_t top_, bottom_;
  int material_;
  std::vector<SandwichFace> faces_;
  std::vector<int64_t> used_;  // the apexes and every corner of the faces reached
};

}  // namespace

int removeFaces(ImprovementMesh& mesh, int64_t a, int64_t b, int64_t c, const SizeCriteria& sizes) {
  if (mesh.isProtectedFace(a, b, c)) return 0;
  const std::vector<int64_t> pair = mesh.tetsWithFace(a, b, c);
  if (pair.size() != 2 || mesh.material(pair[0]) != mesh.material(pair[1])) return 0;
  const auto& p = mesh.points();
  SandwichFace first;
  first.v = {a, b, c};
  first.top_tet = pair[0];
  first.bottom_tet = pair[1];
  if (exactOrientation(p[a], p[b], p[c], p[apexOf(mesh, pair[0], a, b, c)]) < 0)
    std::swap(first.top_tet, first.bottom_tet);
  const int64_t top = apexOf(mesh, first.top_tet, a, b, c), bottom = apexOf(mesh, first.bottom_tet, a, b, c);
  if (mesh.hasEdge(top, bottom)) return 0;
  const int material = mesh.material(pair[0]);

  Sandwich sandwich(mesh, top, bottom, material);
  sandwich.search(first);
  // The disk is chosen under the size bound of every tet the search reached; when a new tet
  // exceeds the bound of the tets it actually removes, it is chosen again under the first two
  // tets' bound, which every removal includes.
  auto boundOf = [&](const std::vector<int64_t>& tets) {
    SizeBound bound;
    bound.criteria = &sizes;
    for (int64_t t : tets) {
      const TetCorners& k = mesh.tet(t);
      bound.include(tetSize(p[k[0]], p[k[1]], p[k[2]], p[k[3]]));
    }
    return bound;
  };
  std::vector<int> chosen;
  std::vector<TetCorners> made;
  double after = sandwich.choose(boundOf(sandwich.removedBy(sandwich.everyFace())), chosen, made);
  if (after != kWorst) {
    const SizeBound removed = boundOf(sandwich.removedBy(chosen));
    for (const TetCorners& t : made)
      if (!removed.admits(material, p[t[0]], p[t[1]], p[t[2]], p[t[3]])) {
        after = sandwich.choose(boundOf(pair), chosen, made);
        break;
      }
  }
  if (after == kWorst) return 0;
  const std::vector<int64_t> old = sandwich.removedBy(chosen);
  double before = std::numeric_limits<double>::infinity();
  double oldVolume = 0, newVolume = 0;
  for (int64_t t : old) {
    before = std::min(before, mesh.quality(t));
    oldVolume += tetVolume(p, mesh.tet(t));
  }
  if (!(after > before)) return 0;
  // Positive new tets around the apexes' edge fill the two cones over the disk once; a rim
  // winding twice around that edge would not, and shows in the volume.
  for (const TetCorners& t : made) newVolume += tetVolume(p, t);
  if (!(std::abs(newVolume - oldVolume) <= 1e-9 * oldVolume)) return 0;
  mesh.replace(old, made, material);
  return static_cast<int>(chosen.size());
}

}  // namespace oraclemesh
