// The sliver rule, beyond the thesis (it is none of the thesis' Rule Sets Q, R, S and T, and
// its steps are named "sliver.*" so that they do not read as the thesis' S1-S3). Rule Set T
// bounds radius-edge ratios, which slivers meet. Once T1-T3 have converged, the sliver rule
// gives each cell inside the materials whose smallest dihedral angle is under
// options_.sliver_dihedral_deg a point near its circumcentre: the best of a few seeded points
// in the ball of radius kSliverPickRadius x circumradius around it, judged by the smallest
// dihedral angle of the cells the point would make (random point placement, Chew 1997, Li &
// Teng 2001; step "sliver.near_centre"). Points in that ball lie inside the sliver's
// circumsphere, so any of them destroys the sliver. A candidate that encroaches a subsegment
// or lies in a surface Delaunay ball is not inserted; when no candidate qualifies, the
// circumcentre is redirected as in T3 ("sliver.segment" splits the subsegment it encroaches
// as T3.1, "sliver.ball_segment" the one its surface ball centre encroaches as T3.2,
// "sliver.ball_centre" inserts that ball centre as T3.3) so segments and restricted facets
// keep their guarantees. Each round gives every sliver one try and T1-T3 then repair what the
// insertions broke; after kSliverRounds the slivers left are listed.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "refine/DihedralAngles.h"
#include "refine/RuleSetTRefiner.h"

namespace oraclemesh::refine {
namespace {

constexpr int kSliverRounds = 4;
constexpr int kSliverCandidates = 12;
constexpr double kSliverPickRadius = 0.4;

}  // namespace

double RuleSetTRefiner::minDihedralDeg(CH c) {
  return refine::minDihedralDeg(toPoint3(c->vertex(0)->point()), toPoint3(c->vertex(1)->point()),
                                toPoint3(c->vertex(2)->point()), toPoint3(c->vertex(3)->point()));
}

// The sliver rule scans every cell each round. Most are far from the bound, and the cosine of
// the smallest angle (no trig) settles those; only cells near or under it get Quality's six
// exact angles, so which cells count as slivers does not change.
bool RuleSetTRefiner::isSliver(CH c) const {
  if (dt_.is_infinite(c) || c->info().label <= 0) return false;
  if (largestDihedralCosine(cornerPoints(c)) < std::cos(options_.sliver_dihedral_deg * M_PI / 180) - 1e-9) return false;
  return minDihedralDeg(c) < options_.sliver_dihedral_deg;
}

// Smallest dihedral angle of the cells that inserting zone.point would make in place of
// conflict cells inside the materials (a new cell's label is not known before insertion;
// the cell it replaces stands in for it); -1 when one of them would fail T3's criteria
// (the repair by T3 would start a cascade of insertions, each with new slivers).
double RuleSetTRefiner::newStarMinDihedral(const Zone& zone) const {
  const Point3 apex = toPoint3(zone.point);
  // A new cell's circumcentre lies at its radius r from the new point, so the sizing field
  // there is at least its value at the point minus grading * r (the field is Lipschitz): a
  // cell that small passes its cell size without a query of the field. The value at the
  // point is read once, on the first cell that needs it.
  const CriteriaTable& criteria = options_.criteria;
  double fieldAtApex = -1;
  auto cellSizeHolds = [&](const MaterialCriteria& crit, int label, const K::Point_3& centre, double r) {
    if (!(criteria.cell_field && crit.from_field.cell_size)) return !(crit.cell_size > 0 && r > crit.cell_size);
    if (fieldAtApex < 0) fieldAtApex = criteria.cell_field->at(apex);
    const double lower = std::min(crit.cell_size, (fieldAtApex - criteria.cell_field->grading() * r) * (1 - 1e-9));
    if (r <= lower) return true;
    const double cellSize = criteria.cellSizeAt(label, toPoint3(centre));
    return !(cellSize > 0 && r > cellSize);
  };
  double worst = 180;
  for (CH c : zone.cells) {
    if (c->info().label <= 0) continue;
    const MaterialCriteria& crit = options_.criteria.of(c->info().label);
    for (int i = 0; i < 4; ++i) {
      if (std::find(zone.cells.begin(), zone.cells.end(), c->neighbor(i)) != zone.cells.end()) continue;
      const VH a = c->vertex((i + 1) & 3), b = c->vertex((i + 2) & 3), d = c->vertex((i + 3) & 3);
      if (dt_.is_infinite(a) || dt_.is_infinite(b) || dt_.is_infinite(d)) continue;
      const auto centre = CGAL::circumcenter(a->point(), b->point(), d->point(), zone.point);
      const double r = std::sqrt(CGAL::squared_distance(centre, zone.point));
      if (!std::isfinite(r)) return -1;  // nearly flat: no circumsphere in doubles, a sliver anyway
      double shortest =
          std::min({CGAL::squared_distance(a->point(), b->point()), CGAL::squared_distance(b->point(), d->point()),
                    CGAL::squared_distance(d->point(), a->point())});
      for (VH w : {a, b, d}) shortest = std::min(shortest, CGAL::squared_distance(w->point(), zone.point));
      shortest = std::sqrt(shortest);
      if (crit.cell_radius_edge_ratio > 0 && r > crit.cell_radius_edge_ratio * shortest) return -1;
      if (!cellSizeHolds(crit, c->info().label, centre, r)) return -1;
      worst = std::min(worst, refine::minDihedralDeg(toPoint3(a->point()), toPoint3(b->point()),
                                                     toPoint3(d->point()), apex));
    }
  }
  return worst;
}

// Whether the sliver rule leaves subsegment s unsplit (the terminator's conditions of T3).
bool RuleSetTRefiner::sliverRefusesSplit(int s, uint64_t stamp, const char* rule) {
  if (nearSmallAngle(segments_[s])) {
    leave("cell", std::string(rule) + " would split a subsegment next to an input angle under 60 degrees", stamp, -1);
    return true;
  }
  if (belowTerminator(segments_[s])) {
    leave("cell", std::string(rule) + " would split a subsegment below the terminator length", stamp, -1);
    return true;
  }
  return false;
}

// One try of the sliver rule on sliver c; true when a point went in.
bool RuleSetTRefiner::refineSliver(CH c, std::mt19937& random) {
  const uint64_t stamp = c->info().stamp;
  const Point3 centre = c->info().circumcentre;
  const double pick = kSliverPickRadius * c->info().radius;
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double bestScore = minDihedralDeg(c);
  Zone best;
  bool found = false;
  for (int k = 0; k <= kSliverCandidates; ++k) {
    Point3 offset{0, 0, 0};
    if (k > 0) do offset = {unit(random), unit(random), unit(random)};
      while (dot(offset, offset) > 1);
    Zone zone = examine(centre + pick * offset, c);
    if (!isFree(zone)) continue;
    Point3 ballCentre;
    if (surfaceBallContaining(zone, ballCentre)) continue;
    const double score = newStarMinDihedral(zone);
    if (score > bestScore) {
      bestScore = score;
      best = std::move(zone);
      found = true;
    }
  }
  if (found) {
    commit(best, 3, -1);
    ++stats_.insertions["sliver.near_centre"];
    return true;
  }
  // No free candidate: the circumcentre goes where T3 would send it.
  const Zone zone = examine(centre, c);
  if (zone.duplicate) {
    leave("cell", "sliver: its circumcentre is a vertex already", stamp, -1);
    return false;
  }
  if (zone.encroached >= 0) {
    if (sliverRefusesSplit(zone.encroached, stamp, "sliver.segment")) return false;
    if (splitEncroached(zone.encroached, "sliver.segment")) return true;
    leave("cell", "sliver: the subsegment its circumcentre encroaches cannot be split", stamp, -1);
    return false;
  }
  Point3 ballCentre;
  int ballEntry = -1;
  if (surfaceBallContaining(zone, ballCentre, &ballEntry)) {
    const Zone surface = examine(ballCentre, c);
    if (!surface.duplicate && surface.encroached >= 0) {
      if (sliverRefusesSplit(surface.encroached, stamp, "sliver.ball_segment")) return false;
      if (splitEncroached(surface.encroached, "sliver.ball_segment")) return true;
    } else if (!surface.duplicate && !belowTerminator(surface) &&
               newStarMinDihedral(surface) > minDihedralDeg(c)) {
      // Only a ball centre whose new cells are better and meet T3's criteria: unlike T3.3,
      // this step is not needed for the guarantees, and under a strict radius-edge bound (1.1
      // on implant_in_bone) a surface point that T3 must repair starts a cascade (3x the tets).
      commit(surface, 2, -1, ballEntry);
      ++stats_.insertions["sliver.ball_centre"];
      return true;
    }
    leave("cell", "sliver: the surface ball centre its circumcentre maps to makes no better cells", stamp, -1);
    return false;
  }
  leave("cell", "sliver: no point near its circumcentre makes better cells", stamp, -1);
  return false;
}

void RuleSetTRefiner::refineSlivers() {
  if (options_.sliver_dihedral_deg <= 0) return;
  control_.report("slivers", 0);
  std::mt19937 random(options_.seed);
  for (int round = 0; round < kSliverRounds; ++round) {
    struct Sliver {
      double angle;
      uint64_t stamp;
      CH cell;
    };
    std::vector<Sliver> slivers;
    for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c)
      if (isSliver(c)) slivers.push_back({minDihedralDeg(c), c->info().stamp, c});
    if (slivers.empty()) return;
    // Worst first; stamps break ties so the order does not depend on memory layout.
    std::sort(slivers.begin(), slivers.end(), [](const Sliver& a, const Sliver& b) {
      return a.angle != b.angle ? a.angle < b.angle : a.stamp < b.stamp;
    });
    int64_t inserted = 0, tried = 0;
    for (const Sliver& s : slivers) {
      if ((++tried & 63) == 0) control_.checkpoint();
      if (s.cell->info().stamp != s.stamp) continue;  // gone with an earlier insertion
      inserted += refineSliver(s.cell, random);
    }
    refine();  // T1-T3 repair what the insertions broke
    if (inserted == 0) return;
  }
}

// Cells inside the materials still under the sliver bound, with the reason the sliver rule
// left them (perturbation, which runs next, works on them).
void RuleSetTRefiner::listLeftSlivers() {
  if (options_.sliver_dihedral_deg <= 0) return;
  constexpr size_t kListed = 200;  // the worst ones; the count is complete
  std::vector<std::pair<double, LeftElement>> left;
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
    if (!isSliver(c)) continue;
    const double angle = minDihedralDeg(c);
    auto it = leftReasons_.find({c->info().stamp, -1});
    const std::string why = it != leftReasons_.end() ? it->second : "made by the last round's T1-T3 repairs";
    std::ostringstream reason;
    reason << "smallest dihedral angle under " << options_.sliver_dihedral_deg << " degrees (" << why << ")";
    left.push_back({angle, {"cell", reason.str(), c->info().circumcentre, c->info().label, angle}});
  }
  std::stable_sort(left.begin(), left.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  stats_.slivers_left_total = static_cast<int64_t>(left.size());
  stats_.slivers_left.clear();
  for (size_t k = 0; k < left.size() && k < kListed; ++k) stats_.slivers_left.push_back(std::move(left[k].second));
}

}  // namespace oraclemesh::refine
