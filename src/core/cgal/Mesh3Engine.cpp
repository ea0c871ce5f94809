// CGAL Mesh_3 driven by the hierarchical oracle. This is one of the two translation units
// allowed to include Mesh_3 headers (8+ minutes of CPU each): keep it small and stable.
#include "cgal/Mesh3Engine.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_domain_with_polyline_features_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>
#include <CGAL/refine_mesh_3.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <thread>
#include <functional>
#include <set>
#include <unordered_map>

#include "Error.h"
#include "features/FeatureSeparation.h"

namespace oraclemesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

Point3 toPoint3(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }
K::Point_3 toCgal(const Point3& p) { return K::Point_3(p[0], p[1], p[2]); }

// Labeled_mesh_domain_3 finds where a dual Voronoi edge crosses the boundary by bisecting
// with the labeling function. Close to a CAD face every bisection step is an exact
// OpenCASCADE classification (milliseconds on B-spline faces), and these steps were most of
// the meshing time. The oracle's composite crossings answer the same question from exact
// line/face intersections; bisection stays as the fallback where the crossings do not
// explain the end labels (a grazing hit the intersector missed).
class OracleLabeledDomain : public CGAL::Labeled_mesh_domain_3<K> {
 public:
  using Base = CGAL::Labeled_mesh_domain_3<K>;

  OracleLabeledDomain(const HierarchicalOracle& oracle, const std::function<int(const Point_3&)>& labeling,
                      const CGAL::Bbox_3& box, FT relativeError, CGAL::Random* random)
      : Base(labeling, box, relativeError, CGAL::Null_subdomain_index(), random), oracle_(&oracle), box_(box) {}

  struct Construct_intersection {
    const OracleLabeledDomain& domain;

    Intersection operator()(const Segment_3& s) const { return between(s.source(), s.target()); }
    Intersection operator()(const Ray_3& r) const { return clipped(r); }
    Intersection operator()(const Line_3& l) const { return clipped(l); }

   private:
    template <typename Query>
    Intersection clipped(const Query& query) const {
      const auto part = CGAL::intersection(query, Iso_cuboid_3(domain.box_));
      if (part)
        if (const Segment_3* s = boost::get<Segment_3>(&*part)) return between(s->source(), s->target());
      return Intersection();
    }

    // The first boundary point from a towards b, with the pair of labels meeting there.
    Intersection between(const Point_3& a, const Point_3& b) const {
      const int labelA = domain.oracle_->label(toPoint3(a));
      const int labelB = domain.oracle_->label(toPoint3(b));
      if (labelA == labelB) return Intersection();
      // Dual edges of hull cells end ~1e16 away: a crossing parameter on such a segment is
      // only good to ~1e16 x 1e-16, so the far end is pulled in along the same line first.
      Point3 from = toPoint3(a), to = toPoint3(b);
      const HierarchicalOracle& oracle = *domain.oracle_;
      const double reach = 2 * oracle.diagonal();
      const bool fromFar = !oracle.bbox().contains(from, reach), toFar = !oracle.bbox().contains(to, reach);
      if (fromFar && toFar) return domain.Base::construct_intersection_object()(Segment_3(a, b));
      auto pullIn = [&](const Point3& near, const Point3& far) {
        const Point3 d = far - near;
        return near + (3 * reach / norm(d)) * d;  // still outside the box, so still outside the domain
      };
      if (fromFar) from = pullIn(to, from);
      if (toFar) to = pullIn(from, to);
      std::vector<CompositeCrossing> crossings;
      try {
        crossings = oracle.crossings(from, to);
      } catch (const Error&) {
        crossings.clear();  // an intersector failure on a degenerate piece: bisect instead
      }
      if (!crossings.empty() && crossings.front().labelBefore == labelA && crossings.back().labelAfter == labelB) {
        const CompositeCrossing& first = crossings.front();
        return Intersection(toCgal(first.point),
                            domain.index_from_surface_patch_index(domain.make_surface_index(labelA, first.labelAfter)),
                            2);
      }
      return domain.Base::construct_intersection_object()(Segment_3(a, b));
    }
  };

  Construct_intersection construct_intersection_object() const { return Construct_intersection{*this}; }

  // The surface patch index Mesh_3 gives the boundary between two labels.
  Surface_patch_index surfacePatchBetween(int labelA, int labelB) const { return make_surface_index(labelA, labelB); }

 private:
  const HierarchicalOracle* oracle_;
  CGAL::Bbox_3 box_;
};

using Domain = CGAL::Mesh_domain_with_polyline_features_3<OracleLabeledDomain>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;
using Point_3 = K::Point_3;
using FT = K::FT;

class PhaseTimer {
 public:
  explicit PhaseTimer(Mesh3Statistics* stats) : stats_(stats) {}
  void finish(const std::string& phase) {
    const auto now = std::chrono::steady_clock::now();
    if (stats_) stats_->seconds[phase] = std::chrono::duration<double>(now - start_).count();
    start_ = now;
  }

 private:
  Mesh3Statistics* stats_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// Mesh_3 asks for sizes with the index of the element it refines: a subdomain index for
// cells, a surface patch index (the pair of subdomains on either side) for facets.
// A facet between two materials takes the finer of their two bounds.
class MaterialSizeField {
 public:
  using SizeAt = double (CriteriaTable::*)(int, const Point3&) const;
  MaterialSizeField(const Domain* domain, const CriteriaTable* table, SizeAt sizeAt)
      : domain_(domain), table_(table), sizeAt_(sizeAt) {}

  FT operator()(const Point_3& p, const int dim, const Domain::Index& index) const {
    const Point3 at{p.x(), p.y(), p.z()};
    if (dim == 3) return (table_->*sizeAt_)(domain_->subdomain_index(index), at);
    if (dim == 2) {
      const auto patch = domain_->surface_patch_index(index);
      double size = std::numeric_limits<double>::infinity();
      for (int material : {patch.first, patch.second})
        if (material > 0) size = std::min(size, (table_->*sizeAt_)(material, at));
      if (std::isfinite(size)) return size;
    }
    return (table_->*sizeAt_)(0, at);  // material 0: the defaults
  }

 private:
  const Domain* domain_;
  const CriteriaTable* table_;
  SizeAt sizeAt_;
};

// The protecting-ball radius Mesh_3 asks for along the features: the features layer's local
// sizes, linear along a curve between its polyline points; at a corner, the smallest size of
// the curve ends there. Curve index k (1-based, Mesh_3's) is polyline k - 1.
class FeatureEdgeSizeField {
 public:
  FeatureEdgeSizeField(const Domain* domain, const FeatureGraph* features,
                       const std::vector<std::vector<double>>* sizes, double edgeSize)
      : domain_(domain), features_(features), sizes_(sizes), edgeSize_(edgeSize) {}

  FT operator()(const Point_3& p, const int dim, const Domain::Index& index) const {
    if (sizes_->size() != features_->polylines.size()) return edgeSize_;
    const Point3 q = toPoint3(p);
    if (dim == 1) {
      const int curve = domain_->curve_index(index);
      if (curve >= 1 && curve <= static_cast<int>(sizes_->size()))
        return edgeSizeOnPolyline(features_->polylines[curve - 1].points, (*sizes_)[curve - 1], q);
    }
    double nearest = std::numeric_limits<double>::infinity();
    for (const FeaturePolyline& pl : features_->polylines)
      nearest = std::min({nearest, distance(pl.points.front(), q), distance(pl.points.back(), q)});
    double size = edgeSize_;
    for (size_t i = 0; i < sizes_->size(); ++i) {
      const std::vector<Point3>& points = features_->polylines[i].points;
      if (points.empty() || (*sizes_)[i].size() != points.size()) continue;
      if (distance(points.front(), q) <= nearest) size = std::min(size, (*sizes_)[i].front());
      if (distance(points.back(), q) <= nearest) size = std::min(size, (*sizes_)[i].back());
    }
    return size;
  }

 private:
  const Domain* domain_;
  const FeatureGraph* features_;
  const std::vector<std::vector<double>>* sizes_;
  double edgeSize_;
};

// Mesh_3's own seeding shoots random rays from the bounding box centre and so misses small
// or hidden boundary components (a thin pin beside a plate). We insert one or more points on
// every face of every input that lies on the composite boundary, computed by Mesh_3's own
// intersection construction so that their indices are what the refiner expects.
int64_t insertBoundarySeeds(C3t3& c3t3, const Domain& domain, const HierarchicalOracle& oracle,
                            const FeatureGraph& features, const CriteriaTable& criteria) {
  const double diag = oracle.diagonal();
  const double probe = 1e-4 * diag;
  const auto intersect = domain.construct_intersection_object();
  const auto cwp = c3t3.triangulation().geom_traits().construct_weighted_point_3_object();
  std::vector<Point3> inserted;
  int64_t count = 0;
  for (const OracleEntry& entry : oracle.entries()) {
    const double spacing =
        2 * (entry.role == Role::Material ? criteria.of(entry.material).facet_size : criteria.defaults.facet_size);
    const double minGap = 0.5 * spacing;
    for (const BoundarySample& s : entry.source->boundarySamples(spacing)) {
      const Point3 a = s.point - probe * s.normal;
      const Point3 b = s.point + probe * s.normal;
      if (oracle.label(a) == oracle.label(b)) continue;  // not on the composite boundary
      // Seeds inside protecting balls would be hidden by them or spoil the protection.
      const double edgeClearance = 2 * criteria.strictest(&MaterialCriteria::edge_size, false);
      bool nearFeature = false;
      for (const FeaturePolyline& pl : features.polylines) {
        for (size_t i = 0; i + 1 < pl.points.size() && !nearFeature; ++i)
          nearFeature = distanceToSegment(s.point, pl.points[i], pl.points[i + 1]) < edgeClearance;
        if (nearFeature) break;
      }
      if (nearFeature) continue;
      const bool crowded = std::any_of(inserted.begin(), inserted.end(),
                                       [&](const Point3& q) { return distance(q, s.point) < minGap; });
      if (crowded) continue;
      const auto hit = intersect(K::Segment_3(toCgal(a), toCgal(b)));
      if (std::get<2>(hit) == 0) continue;  // Mesh_3 found no crossing (within its error)
      auto v = c3t3.triangulation().insert(cwp(std::get<0>(hit)));
      if (v == Tr::Vertex_handle()) continue;  // hidden by a protecting ball
      c3t3.set_dimension(v, 2);
      c3t3.set_index(v, std::get<1>(hit));
      inserted.push_back(s.point);
      ++count;
    }
  }
  return count;
}

// Bisection stops at relative_error_bound x diagonal; the pipeline then projects boundary
// vertices exactly onto the CAD, so this only needs to be small against the mesh size.
const FT kRelativeBisectionError = 1e-6;

CGAL::Bbox_3 meshingBox(const HierarchicalOracle& oracle) {
  const Bbox box = oracle.bbox();
  const double margin = 0.02 * box.diagonal();
  return CGAL::Bbox_3(box.min[0] - margin, box.min[1] - margin, box.min[2] - margin, box.max[0] + margin,
                      box.max[1] + margin, box.max[2] + margin);
}

void throwIfCancelledOrLate(const RunControl& control) {
  if (control.cancelRequested()) throw Cancelled();
  control.checkpoint();  // throws the time-limit LimitError once the limit has passed
}

// Perturbation then exudation, the sliver removal of every engine. The optimizers take no
// stop flag, only a time limit: each gets what is left of the job's limit (0 = none for
// CGAL), so limits.time_limit holds in every phase.
void removeSlivers(C3t3& c3t3, const Domain& domain, const Mesh3Options& options, const RunControl& control,
                   PhaseTimer& timer) {
  namespace p = CGAL::parameters;
  auto optimizerTimeLimit = [&]() {
    double limit = options.optimize_time_limit > 0 ? options.optimize_time_limit : std::numeric_limits<double>::infinity();
    limit = std::min(limit, control.remainingSeconds());
    return std::isfinite(limit) ? std::max(limit, 1e-3) : 0.0;
  };
  if (options.perturb) {
    control.report("perturb", 0);
    // Perturbation only works on slivers below the bound: with no bound it keeps trying to
    // raise the worst angle until the time limit, which makes the result machine-dependent.
    CGAL::perturb_mesh_3(c3t3, domain, p::time_limit = optimizerTimeLimit(), p::sliver_bound = options.sliver_bound);
    throwIfCancelledOrLate(control);
  }
  timer.finish("perturb");
  if (options.exude) {
    control.report("exude", 0);
    CGAL::exude_mesh_3(c3t3, p::time_limit = optimizerTimeLimit(), p::sliver_bound = options.sliver_bound);
    throwIfCancelledOrLate(control);
  }
  timer.finish("exude");
}

TetMesh extractTetMesh(const C3t3& c3t3, const Domain& domain, const std::vector<int>& curveIdOfIndex) {
  TetMesh mesh;
  std::unordered_map<Tr::Vertex_handle, int64_t> index;
  auto indexOf = [&](Tr::Vertex_handle v) {
    auto [it, added] = index.emplace(v, static_cast<int64_t>(mesh.points.size()));
    if (added) {
      mesh.points.push_back(toPoint3(c3t3.triangulation().point(v).point()));
      const int dim = c3t3.in_dimension(v);
      mesh.vertex_dimension.push_back(dim);
      int curve = -1;
      if (dim == 1) {
        const int curveIndex = domain.curve_index(c3t3.index(v));
        if (curveIndex > 0 && curveIndex < static_cast<int>(curveIdOfIndex.size())) curve = curveIdOfIndex[curveIndex];
      }
      mesh.vertex_curve.push_back(curve);
    }
    return it->second;
  };
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    // CGAL cells are positively oriented, which is the orientation TetMesh promises.
    mesh.tets.push_back({indexOf(c->vertex(0)), indexOf(c->vertex(1)), indexOf(c->vertex(2)), indexOf(c->vertex(3))});
    mesh.tet_materials.push_back(c3t3.subdomain_index(c));
  }
  // A protected edge can be an edge of the triangulation whose cells all lie outside the
  // complex (their circumcentres outside every material: a sharp edge along a thin wedge,
  // screw.step at the default size); the mesh would lose it. As the thesis engine's last
  // resort for T1.3, the cells around it whose barycentre lies in a material are taken with
  // that material.
  const Tr& tr = c3t3.triangulation();
  std::set<Tr::Cell_handle> takenAroundEdges;
  for (auto e = c3t3.edges_in_complex_begin(); e != c3t3.edges_in_complex_end(); ++e) {
    auto circ = tr.incident_cells(*e), done = circ;
    bool inComplex = false;
    do inComplex = inComplex || c3t3.is_in_complex(circ);
    while (++circ != done);
    if (inComplex) continue;
    do {
      if (tr.is_infinite(circ) || takenAroundEdges.count(circ)) continue;
      const Point_3 barycentre = CGAL::centroid(tr.point(circ->vertex(0)).point(), tr.point(circ->vertex(1)).point(),
                                                tr.point(circ->vertex(2)).point(), tr.point(circ->vertex(3)).point());
      const auto label = domain.is_in_domain_object()(barycentre);
      if (!label) continue;
      takenAroundEdges.insert(circ);
      mesh.tets.push_back(
          {indexOf(circ->vertex(0)), indexOf(circ->vertex(1)), indexOf(circ->vertex(2)), indexOf(circ->vertex(3))});
      mesh.tet_materials.push_back(static_cast<int>(*label));
    } while (++circ != done);
  }
  for (auto e = c3t3.edges_in_complex_begin(); e != c3t3.edges_in_complex_end(); ++e) {
    const Tr::Vertex_handle a = e->first->vertex(e->second);
    const Tr::Vertex_handle b = e->first->vertex(e->third);
    auto ia = index.find(a), ib = index.find(b);
    if (ia == index.end() || ib == index.end()) continue;  // edge of no meshed cell
    mesh.feature_edges.push_back({ia->second, ib->second});
    const int curveIndex = c3t3.curve_index(*e);
    mesh.feature_edge_curves.push_back(
        curveIndex > 0 && curveIndex < static_cast<int>(curveIdOfIndex.size()) ? curveIdOfIndex[curveIndex] : -1);
  }
  return mesh;
}

}  // namespace

TetMesh meshWithCgalMesh3(const HierarchicalOracle& oracle, const FeatureGraph& features,
                          const Mesh3Options& options, const RunControl& control, Mesh3Statistics* statistics) {
  PhaseTimer timer(statistics);

  // The stop flag is how Mesh_3's refinement and edge protection are interrupted. A watchdog
  // raises it on cancel or time-out, whatever phase is running; the labeling function, called
  // constantly, reports progress on the way.
  std::atomic<bool> stop{false};
  std::atomic<bool> finished{false};
  std::thread watchdog([&] {
    while (!finished && !stop) {
      if (control.cancelRequested()) stop = true;
      if (control.remainingSeconds() <= 0) stop = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  struct JoinOnExit {
    std::atomic<bool>& finished;
    std::thread& thread;
    ~JoinOnExit() {
      finished = true;
      thread.join();
    }
  } joinWatchdog{finished, watchdog};

  int64_t calls = 0;
  const C3t3* progressSource = nullptr;
  std::string phase = "protect features";
  const double expectedVertices = std::max<double>(1000.0, static_cast<double>(options.max_vertices) / 50.0);
  std::function<int(const Point_3&)> labeling = [&](const Point_3& p) {
    if ((++calls & 4095) == 0 && progressSource && phase == "refine")
      control.report(phase, std::min(0.99, progressSource->triangulation().number_of_vertices() / expectedVertices));
    return oracle.label(toPoint3(p));
  };

  CGAL::Random random(options.seed);
  Domain domain(oracle, labeling, meshingBox(oracle), kRelativeBisectionError, &random);

  std::vector<int> curveIdOfIndex(1, -1);  // Mesh_3 curve indices start at 1
  if (!features.empty()) {
    std::vector<std::vector<Point_3>> polylines;
    for (const FeaturePolyline& pl : features.polylines) {
      std::vector<Point_3> line;
      for (const Point3& p : pl.points) line.push_back(toCgal(p));
      polylines.push_back(std::move(line));
      curveIdOfIndex.push_back(pl.curve);
    }
    domain.add_features(polylines.begin(), polylines.end());
  }

  const CriteriaTable& table = options.criteria;
  const double radiusEdge = table.strictest(&MaterialCriteria::cell_radius_edge_ratio, true);
  const double facetAngle = std::min(30.0, table.strictest(&MaterialCriteria::facet_angle, false));
  const double edgeSize = table.strictest(&MaterialCriteria::edge_size, true);
  if (statistics) {
    statistics->radius_edge_ratio_used = radiusEdge;
    statistics->facet_angle_used = facetAngle;
  }
  namespace p = CGAL::parameters;
  const FeatureEdgeSizeField edgeSizes(&domain, &features, &options.feature_edge_sizes, edgeSize);
  Criteria criteria(p::edge_size = edgeSizes, p::facet_angle = facetAngle,
                    p::facet_size = MaterialSizeField(&domain, &table, &CriteriaTable::facetSizeAt),
                    p::facet_distance = MaterialSizeField(&domain, &table, &CriteriaTable::facetDistanceAt),
                    p::cell_radius_edge_ratio = radiusEdge,
                    p::cell_size = MaterialSizeField(&domain, &table, &CriteriaTable::cellSizeAt));

  C3t3 c3t3;
  progressSource = &c3t3;
  CGAL::Mesh_error_code errorCode = CGAL::CGAL_MESH_3_NO_ERROR;
  const std::size_t maxVertices = options.max_vertices > 0 ? static_cast<std::size_t>(options.max_vertices) : 0;
  auto throwIfStopped = [&](const char* phase) {
    throwIfCancelledOrLate(control);
    if (errorCode == CGAL::CGAL_MESH_3_MAXIMAL_NUMBER_OF_VERTICES_REACHED)
      throw LimitError(std::string("the mesh reached limits.max_vertices = ") + std::to_string(options.max_vertices) +
                       " vertices during " + phase + ": coarsen cell_size / facet_size / facet_distance or raise the limit");
  };

  control.report("protect features", 0);
  if (!features.empty()) {
    CGAL::Mesh_3::internal::init_c3t3_with_features(c3t3, domain, criteria, false, maxVertices, &errorCode, &stop);
    throwIfStopped("feature protection");
    if (statistics) statistics->protecting_balls = static_cast<int64_t>(c3t3.triangulation().number_of_vertices());
  }
  timer.finish("protect_features");

  const int64_t seeds = insertBoundarySeeds(c3t3, domain, oracle, features, table);
  if (statistics) statistics->initial_points = seeds;
  timer.finish("seed");

  phase = "refine";
  control.report(phase, 0);
  CGAL::refine_mesh_3(c3t3, domain, criteria, p::no_perturb(), p::no_exude(), p::no_reset_c3t3(),
                      p::mesh_3_options(p::maximal_number_of_vertices = maxVertices,
                                        p::pointer_to_error_code = &errorCode,
                                        p::pointer_to_stop_atomic_boolean = &stop));
  throwIfStopped("refinement");
  if (c3t3.number_of_cells_in_complex() == 0)
    throw NoTetrahedraError("Mesh_3 produced no tetrahedra: the inputs may be smaller than the sizes asked for; "
                     "lower cell_size and facet_size below the smallest part's thickness.");
  timer.finish("refine");

  phase = "optimize";  // the labeling function reports refinement progress only
  removeSlivers(c3t3, domain, options, control, timer);
  TetMesh mesh = extractTetMesh(c3t3, domain, curveIdOfIndex);
  timer.finish("extract");
  return mesh;
}

}  // namespace oraclemesh
