// Rule P, vertex moves, beyond the thesis (none of its rule sets has a rule P). The sliver
// rule leaves slivers whose circumcentre maps to a surface ball centre that makes no better
// cells (implant_in_bone (a): about 400 of them). Moving one of a sliver's corners
// instead, as CGAL's perturb_mesh_3 does, lifts most of them without new points; doing it
// here, on the engine's own triangulation, spares the pipeline rebuilding a Mesh_3 complex
// for CGAL's perturber (on implant_in_bone (a) that rebuild and perturbation took a third
// of the job). A move keeps the mesh's guarantees or is undone: only interior and surface
// corners move (never segment vertices, bounding corners or vertices the planar-face layer
// tracks), a surface corner goes back onto the boundary through the oracle's projection,
// and a move stays only when the smallest dihedral angle of the cells it replaces rises,
// every subsegment there stays an unencroached edge of a labelled cell (T1.3), and every new
// facet between two labels is a restricted facet on boundary vertices that meets the facet
// criteria. CGAL's
// perturbation still runs on whatever is left (Pipeline). Candidate targets are screened
// cheaply first: the corner's cells with the corner moved, before any Delaunay update.
#include <algorithm>
#include <cmath>
#include <limits>

#include "Error.h"
#include "refine/DihedralAngles.h"
#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {
namespace {

constexpr int kPerturbRounds = 24;
constexpr int kPerturbPlainRounds = 6;  // then the slivers left get more effort
constexpr int kPerturbMaxEffort = 16;    // x kPerturbCandidates targets per corner
constexpr int kPerturbMaxTries = 12;     // moves tried per sliver and round at most
constexpr int kPerturbIdleWidest = 3;    // rounds at kPerturbMaxEffort that move nothing
constexpr double kIntoCircumsphere = 0.9; // x radius: where a neighbour's vertex goes
constexpr int kPerturbCandidates = 10;  // targets screened per corner
constexpr int kPerturbMoves = 3;        // moves tried per sliver and round (x effort)
constexpr double kPerturbMaxStep = 0.4; // x the sliver's shortest edge

}  // namespace

bool RuleSetTRefiner::movable(VH v) const {
  if (dt_.is_infinite(v) || v->info().far || v->info().dimension <= 1) return false;
  return !hook_ || !hook_->pinsVertex(v);
}

// The smallest dihedral angle of cell c with corner `moved` at p (none: VH()), its corners
// taken by vertex id: the order CGAL stores them in depends on memory layout once vertices
// have moved, and the rounding must not.
double RuleSetTRefiner::minDihedralById(CH c, VH moved, const CgalPoint& p) const {
  std::array<std::pair<int64_t, Point3>, 4> corners;
  for (int k = 0; k < 4; ++k)
    corners[k] = {c->vertex(k)->info().id, toPoint3(c->vertex(k) == moved ? p : c->vertex(k)->point())};
  std::sort(corners.begin(), corners.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  return smallestDihedralDeg({corners[0].second, corners[1].second, corners[2].second, corners[3].second});
}

// Smallest dihedral angle of the labelled cells of `star` (the cells of v) with v at p,
// the cells kept as they are; -1 when one would turn flat or inside out. Stops at the first
// cell no better than `floor` (the result is then no better than floor either).
double RuleSetTRefiner::starMinWithVertexAt(VH v, const std::vector<CH>& star, const CgalPoint& p, double floor) const {
  double worst = 180;
  for (CH c : star) {
    if (dt_.is_infinite(c)) continue;
    std::array<CgalPoint, 4> q;
    for (int k = 0; k < 4; ++k) q[k] = c->vertex(k) == v ? p : c->vertex(k)->point();
    if (CGAL::orientation(q[0], q[1], q[2], q[3]) != CGAL::POSITIVE) return -1;
    if (c->info().label <= 0) continue;
    worst = std::min(worst, minDihedralById(c, v, p));
    if (worst <= floor) return worst;
  }
  return worst;
}

// Screened moves of sliver c's movable corners, best first: away from the opposite face
// (the sliver's volume grows) with a seeded random tilt, steps up to kPerturbMaxStep x its
// shortest edge. A candidate is kept only when it beats every earlier one of the sliver
// (branch and bound: the first cell no better ends its screening). Moves after which the
// corner's cells stay Delaunay come first: the screen then predicts the move's outcome,
// while a move that flips cells often ends worse than it screened (implant_in_bone (a):
// the last slivers' largest steps screened at 20-25 degrees and made cells of 7-10).
std::vector<RuleSetTRefiner::VertexMove> RuleSetTRefiner::screenedMoves(CH c, std::mt19937& random, int effort) const {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double scale = shortestEdge(c);
  std::vector<VertexMove> moves;
  // Corners by vertex id, so the seeded draws go to the same corners in every run.
  std::array<int, 4> corners{0, 1, 2, 3};
  std::sort(corners.begin(), corners.end(),
            [&](int x, int y) { return c->vertex(x)->info().id < c->vertex(y)->info().id; });
  // Two lists: moves whose star stays Delaunay (the move then makes exactly the screened
  // cells) and the others (the triangulation flips, so the move may end worse).
  std::vector<VertexMove> kept, flipping;
  double best = -1, bestFlipping = -1;
  for (int k : corners) {
    const VH v = c->vertex(k);
    if (!movable(v)) continue;
    std::vector<CH> star;
    dt_.incident_cells(v, std::back_inserter(star));
    const double before = starMinWithVertexAt(v, star, v->point(), -1);
    std::array<Point3, 3> face;  // the opposite face, by vertex id
    for (int n = 0, m = 0; n < 4; ++n)
      if (corners[n] != k) face[m++] = toPoint3(c->vertex(corners[n])->point());
    const Point3 p = toPoint3(v->point()), a = face[0], b = face[1], d = face[2];
    Point3 away = cross(b - a, d - a);
    const double len = norm(away);
    if (!(len > 0)) continue;
    away = (dot(away, p - a) < 0 ? -1.0 : 1.0) / len * away;
    // A surface corner moves in its tangent plane (the oracle's projection would undo the
    // rest): there a flat sliver's opposite face is about parallel to the surface, so the
    // seeded tilt leads and the move is screened where the projection will put it.
    const Point3 normal = v->info().dimension == 2 ? surfaceNormalAt(v, star) : Point3{0, 0, 0};
    const bool onSurface = dot(normal, normal) > 0;
    const int candidates = kPerturbCandidates * effort;
    for (int j = 0; j < candidates; ++j) {
      Point3 tilt;
      do tilt = {unit(random), unit(random), unit(random)};
      while (dot(tilt, tilt) > 1);
      const double step = kPerturbMaxStep * scale * (j + 1) / candidates;
      Point3 direction = onSurface ? 0.3 * away + tilt : away + 0.7 * tilt;
      if (onSurface) direction = direction - dot(direction, normal) * normal;
      if (!(norm(direction) > 0)) continue;
      const Point3 target = p + (step / norm(direction)) * direction;
      if (step < terminatorAt(target)) continue;  // refused by the move (cellsChangedByMove)
      const double floor = std::max(before, best);
      const double score = starMinWithVertexAt(v, star, toCgal(target), floor);
      if (score <= floor) continue;
      if (starStaysDelaunay(v, star, toCgal(target))) {
        best = score;
        kept.push_back({v, target, before, score});
      } else if (score > bestFlipping) {
        bestFlipping = score;
        flipping.push_back({v, target, before, score});
      }
    }
  }
  // Scores rose along each list: the best kept move first, flipping ones last.
  moves.assign(kept.rbegin(), kept.rend());
  if (effort >= kPerturbMaxEffort) intoCircumsphereMoves(c, scale, moves);
  moves.insert(moves.end(), flipping.rbegin(), flipping.rend());
  return moves;
}

// Last resort for a sliver its own corners cannot lift: the movable vertex of a neighbour
// (across one of its facets) moved just inside the sliver's circumsphere, which deletes
// the sliver. Slivers' neighbours are about cospherical with them, so the step is short;
// the move's cells are unknown before it is made (score 0: tryVertexMove judges it).
void RuleSetTRefiner::intoCircumsphereMoves(CH c, double scale, std::vector<VertexMove>& moves) const {
  std::array<VH, 4> corners{c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
  std::sort(corners.begin(), corners.end(), [](VH x, VH y) { return x->info().id < y->info().id; });
  const Point3 centre = toPoint3(CGAL::circumcenter(corners[0]->point(), corners[1]->point(), corners[2]->point(),
                                                    corners[3]->point()));
  const double radius = distance(centre, toPoint3(corners[0]->point()));
  if (!isFinite(centre) || !std::isfinite(radius)) return;  // four coplanar corners: no sphere
  std::vector<VH> across;
  for (int i = 0; i < 4; ++i) {
    const CH n = c->neighbor(i);
    const VH w = n->vertex(n->index(c));
    if (movable(w)) across.push_back(w);
  }
  std::sort(across.begin(), across.end(), [](VH x, VH y) { return x->info().id < y->info().id; });
  for (VH w : across) {
    const Point3 p = toPoint3(w->point());
    const double out = distance(p, centre);
    const double step = out - kIntoCircumsphere * radius;
    if (!(out > 0) || step > kPerturbMaxStep * scale) continue;
    const Point3 target = p + (step / out) * (centre - p);
    if (step < terminatorAt(target)) continue;  // refused by the move (cellsChangedByMove)
    std::vector<CH> star;
    dt_.incident_cells(w, std::back_inserter(star));
    moves.push_back({w, target, starMinWithVertexAt(w, star, w->point(), -1), 0});
  }
}

// Whether the cells of v (`star`) stay a Delaunay triangulation with v moved to p: no
// vertex across one of their facets lies inside or on the circumsphere of the moved cell.
// Then moving v makes exactly these cells and the screened score is the move's outcome.
bool RuleSetTRefiner::starStaysDelaunay(VH v, const std::vector<CH>& star, const CgalPoint& p) const {
  for (CH c : star) {
    if (dt_.is_infinite(c)) return false;
    std::array<CgalPoint, 4> q;
    for (int k = 0; k < 4; ++k) q[k] = c->vertex(k) == v ? p : c->vertex(k)->point();
    for (int i = 0; i < 4; ++i) {
      const CH n = c->neighbor(i);
      const VH across = n->vertex(n->index(c));
      if (dt_.is_infinite(across)) continue;
      if (CGAL::side_of_oriented_sphere(q[0], q[1], q[2], q[3], across->point()) != CGAL::ON_NEGATIVE_SIDE)
        return false;
    }
  }
  return true;
}

// Unit normal of the boundary at surface vertex v: the mean of the normals of the restricted
// facets at v (their sides made to agree with the first); zero when v has none. Facets and
// their corners go by vertex id: the star's order and the cells' corner order depend on
// memory layout once vertices have moved, and the rounding must not.
Point3 RuleSetTRefiner::surfaceNormalAt(VH v, const std::vector<CH>& star) const {
  std::vector<std::array<VH, 3>> facets;
  for (CH c : star) {
    const int at = c->index(v);
    for (int i = 0; i < 4; ++i) {
      if (i == at || !c->info().facets[i].restricted) continue;
      std::array<VH, 3> f{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
      std::sort(f.begin(), f.end(), [](VH x, VH y) { return x->info().id < y->info().id; });
      facets.push_back(f);
    }
  }
  const auto ids = [](const std::array<VH, 3>& f) {
    return std::array<int64_t, 3>{f[0]->info().id, f[1]->info().id, f[2]->info().id};
  };
  std::sort(facets.begin(), facets.end(), [&](const auto& x, const auto& y) { return ids(x) < ids(y); });
  facets.erase(std::unique(facets.begin(), facets.end()), facets.end());  // seen from both sides
  Point3 sum{0, 0, 0};
  for (const auto& f : facets) {
    const Point3 a = toPoint3(f[0]->point()), b = toPoint3(f[1]->point()), d = toPoint3(f[2]->point());
    Point3 n = cross(b - a, d - a);
    const double len = norm(n);
    if (!(len > 0)) continue;
    n = (dot(n, sum) < 0 ? -1.0 : 1.0) / len * n;
    sum = sum + n;
  }
  const double len = norm(sum);
  return len > 0 ? (1.0 / len) * sum : Point3{0, 0, 0};
}

// The cells moving v to target deletes (v's cells and the target's conflict zone) and the
// alive subsegments among their edges; false when target is a vertex already or, unless the
// move is an undo, closer than the terminator length there to one. An undo puts v back where
// it was: the terminator at its origin may be longer than the step the move took to a point
// where the sizing field is smaller, and v was there before.
bool RuleSetTRefiner::cellsChangedByMove(VH v, const Point3& target, bool undo, std::vector<CH>& cells,
                                         std::vector<int>& segments) const {
  Zone zone = examine(target, v->cell());
  if (zone.duplicate || (!undo && belowTerminator(zone))) return false;
  cells = std::move(zone.cells);
  std::vector<CH> star;
  dt_.incident_cells(v, std::back_inserter(star));
  for (CH c : star)
    if (std::find(cells.begin(), cells.end(), c) == cells.end()) cells.push_back(c);
  segments.clear();
  for (CH c : cells)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const VH va = c->vertex(a), vb = c->vertex(b);
        if (dt_.is_infinite(va) || dt_.is_infinite(vb)) continue;
        auto it = segmentOf_.find(pairKey(va->info().id, vb->info().id));
        if (it != segmentOf_.end() && std::find(segments.begin(), segments.end(), it->second) == segments.end())
          segments.push_back(it->second);
      }
  return true;
}

std::array<int64_t, 4> RuleSetTRefiner::cornerIds(CH c) const {
  std::array<int64_t, 4> ids;
  for (int k = 0; k < 4; ++k) ids[k] = dt_.is_infinite(c->vertex(k)) ? -1 : c->vertex(k)->info().id;
  std::sort(ids.begin(), ids.end());
  return ids;
}

// Moves v to target in the triangulation and evaluates the new cells and their facets, in
// an order that does not depend on memory layout (stamps break ties elsewhere). A cell
// found in `before` (by its corners: an undo restores the cells the move deleted) takes
// its saved evaluation back, with its facets on both sides, instead of asking the oracle.
std::vector<CH> RuleSetTRefiner::relocate(VH v, const Point3& target, const std::vector<CH>& changed,
                                           const std::map<std::array<int64_t, 4>, SavedCell>* before) {
  for (CH c : changed) c->info().stamp = 0;  // queued entries of deleted cells read as stale
  nearMaterial_.erase(nearMaterial_.lower_bound({v->info().id, std::numeric_limits<int>::min()}),
                      nearMaterial_.upper_bound({v->info().id, std::numeric_limits<int>::max()}));
  std::vector<CH> fresh;
  dt_.move_if_no_collision_and_give_new_cells(v, toCgal(target), std::back_inserter(fresh));
  std::vector<std::pair<std::array<int64_t, 4>, CH>> ordered;
  for (CH c : fresh) ordered.emplace_back(cornerIds(c), c);
  std::sort(ordered.begin(), ordered.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  fresh.clear();
  for (const auto& [ids, c] : ordered) {
    fresh.push_back(c);
    auto saved = before ? before->find(ids) : before->end();
    if (!before || saved == before->end()) {
      evaluateCell(c);
      continue;
    }
    c->info() = saved->second.info;
    c->info().stamp = ++stampCounter_;
    for (int i = 0; i < 4; ++i) {
      const auto& was = saved->second.corners;
      c->info().facets[i] = saved->second.info.facets[std::find(was.begin(), was.end(), c->vertex(i)) - was.begin()];
      c->neighbor(i)->info().facets[c->neighbor(i)->index(c)] = c->info().facets[i];
    }
  }
  for (CH c : fresh)
    for (int i = 0; i < 4; ++i)
      if (!c->info().facets[i].known) evaluateFacet(c, i);
  return fresh;
}

double RuleSetTRefiner::smallestLabelledAngle(const std::vector<CH>& cells) const {
  double worst = 180;
  for (CH c : cells)
    if (!dt_.is_infinite(c) && c->info().label > 0) worst = std::min(worst, minDihedralById(c, VH(), CgalPoint()));
  return worst;
}

// The guarantees a move must keep (see above), checked on the cells it made.
bool RuleSetTRefiner::moveKeepsGuarantees(VH v, const std::vector<CH>& fresh, const std::vector<int>& segments) const {
  for (int s : segments) {
    const Subsegment& seg = segments_[s];
    if (!seg.alive) continue;
    CH c;
    int i, j;
    if (!dt_.is_edge(seg.a, seg.b, c, i, j) || strictlyInDiametralBall(v->point(), seg)) return false;
    if (outsideEveryMaterial(seg)) return false;  // the mesh would lose it (T1.3)
  }
  for (CH c : fresh)
    for (int i = 0; i < 4; ++i) {
      const CH n = c->neighbor(i);
      const int labelHere = dt_.is_infinite(c) ? 0 : c->info().label;
      const int labelThere = dt_.is_infinite(n) ? 0 : n->info().label;
      if (c->info().facets[i].restricted ? facetBadness(c, i) > 0 : labelHere != labelThere) return false;
    }
  return true;
}

// Moves v to target if that keeps the guarantees and raises the smallest dihedral angle of
// the labelled cells it changes; else puts v back (the Delaunay triangulation of the same
// points is the same). True when the move stays; the cells made, by the move or its undo,
// are added to `made`.
bool RuleSetTRefiner::tryVertexMove(VH v, const Point3& target, std::vector<CH>& made) {
  const Point3 origin = toPoint3(v->point());
  std::vector<CH> changed;
  std::vector<int> segments;
  if (!cellsChangedByMove(v, target, false, changed, segments)) return false;
  const double before = smallestLabelledAngle(changed);
  std::map<std::array<int64_t, 4>, SavedCell> saved;
  for (CH c : changed)
    saved.emplace(cornerIds(c), SavedCell{c->info(), {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)}});
  const std::vector<CH> fresh = relocate(v, target, changed);
  if (smallestLabelledAngle(fresh) > before && moveKeepsGuarantees(v, fresh, segments)) {
    made.insert(made.end(), fresh.begin(), fresh.end());
    return true;
  }
  std::vector<int> unused;
  if (!cellsChangedByMove(v, origin, true, changed, unused))
    throw Error("internal error: the thesis engine could not undo a vertex move");
  const std::vector<CH> restored = relocate(v, origin, changed, &saved);
  made.insert(made.end(), restored.begin(), restored.end());
  return false;
}

// One try of rule P on sliver c (up to kPerturbMoves x effort moves, so the few slivers of
// the late rounds also reach the screen's lesser candidates, which a corner's guarantees
// may need); true when a corner moved. c may be gone afterwards either way: the cells made
// in its place are added to `made`.
bool RuleSetTRefiner::perturbSliver(CH c, std::mt19937& random, int effort, std::vector<CH>& made) {
  int tries = 0;
  for (const VertexMove& m : screenedMoves(c, random, effort)) {
    if (tries == std::min(kPerturbMoves * effort, kPerturbMaxTries)) break;
    Point3 target = m.target;
    // Targets must be finite before the oracle or the exact predicates see them (GMP raises
    // SIGFPE on NaN): a flat sliver's circumcentre is at infinity.
    if (!isFinite(target)) continue;
    int targetEntry = -1;
    if (m.vertex->info().dimension == 2) {
      const BoundaryProjection onBoundary = oracle_.projectOnBoundary(target, &targetEntry);
      if (!std::isfinite(onBoundary.distance)) continue;
      target = onBoundary.point;
      std::vector<CH> star;
      dt_.incident_cells(m.vertex, std::back_inserter(star));
      if (m.score > 0 && starMinWithVertexAt(m.vertex, star, toCgal(target), m.before) <= m.before) continue;
    }
    // A step under the terminator length is refused by the move (see cellsChangedByMove):
    // no try is spent on it.
    if (distance(target, toPoint3(m.vertex->point())) < terminatorAt(target)) continue;
    ++tries;
    if (tryVertexMove(m.vertex, target, made)) {
      // An undone move leaves v where it was, with the entry it had.
      m.vertex->info().boundaryEntry = targetEntry;
      ++stats_.vertex_moves;
      return true;
    }
  }
  return false;
}

void RuleSetTRefiner::trackIfSliver(CH c, std::vector<TrackedCell>& slivers) const {
  if (dt_.is_infinite(c) || c->info().label <= 0) return;
  const double angle = minDihedralById(c, VH(), CgalPoint());
  if (angle < options_.sliver_dihedral_deg) slivers.push_back({angle, c->info().stamp, c});
}

void RuleSetTRefiner::perturbSlivers() {
  if (options_.sliver_dihedral_deg <= 0) return;
  control_.report("vertex moves", 0);
  movingVertices_ = true;
  std::mt19937 random(options_.seed + 1);
  // The first round looks at every cell; later ones at the slivers still there and the
  // cells the moves made.
  std::vector<TrackedCell> slivers;
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) trackIfSliver(c, slivers);
  int effort = 1, idleWidest = 0;
  for (int round = 0; round < kPerturbRounds && !slivers.empty(); ++round) {
    std::sort(slivers.begin(), slivers.end(), [](const TrackedCell& x, const TrackedCell& y) {
      return x.angle != y.angle ? x.angle < y.angle : x.stamp < y.stamp;
    });
    // A cell can be listed twice: a later try may make it in the memory of a cell an
    // earlier try made and deleted, which depends on memory layout. Each visit draws from
    // `random`, so a second one would make the mesh depend on that layout.
    slivers.erase(std::unique(slivers.begin(), slivers.end(),
                              [](const TrackedCell& x, const TrackedCell& y) { return x.stamp == y.stamp; }),
                  slivers.end());
    // The few slivers the first rounds leave get more candidates each, and more again
    // after a round that moved nothing (the last ones need the rare targets that keep
    // their corner's cells Delaunay and their guarantees).
    if (round == kPerturbPlainRounds) effort = std::max(effort, 4);
    std::vector<std::pair<uint64_t, CH>> made;  // stamp, cell
    std::vector<TrackedCell> next;
    int64_t moved = 0, tried = 0;
    for (const TrackedCell& s : slivers) {
      if ((++tried & 63) == 0) control_.checkpoint();
      if (s.cell->info().stamp != s.stamp) continue;  // changed by an earlier move
      std::vector<CH> cells;
      moved += perturbSliver(s.cell, random, effort, cells);
      // Cells made by an undone try may be gone with the next try (stamp 0).
      for (CH c : cells)
        if (c->info().stamp != 0) made.emplace_back(c->info().stamp, c);
      if (s.cell->info().stamp == s.stamp) next.push_back(s);
    }
    if (moved == 0) {
      if (effort >= kPerturbMaxEffort && ++idleWidest == kPerturbIdleWidest) return;
      effort = std::min(4 * effort, kPerturbMaxEffort);
    }
    for (const auto& [stamp, c] : made)
      if (c->info().stamp == stamp) trackIfSliver(c, next);
    // A sliver kept in `next` may have been changed by a later move of the round.
    next.erase(std::remove_if(next.begin(), next.end(),
                              [](const TrackedCell& s) { return s.cell->info().stamp != s.stamp; }),
               next.end());
    slivers.swap(next);
  }
}

}  // namespace oraclemesh::refine
