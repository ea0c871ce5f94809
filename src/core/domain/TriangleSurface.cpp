#include "domain/TriangleSurface.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "Error.h"
#include "domain/TriangleSurfaceFile.h"

namespace oraclemesh {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using KPoint = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<KPoint>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Traits = CGAL::AABB_traits<Kernel, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, Kernel, CGAL::Default, Tree>;

struct TriangleSurface::Impl {
  std::string name;
  Mesh mesh;
  std::unique_ptr<Tree> tree;
  std::unique_ptr<Side> side;
  Bbox box;
  double volume = 0;
  std::vector<std::size_t> component;  // connected component of each face
  std::size_t componentCount = 0;

  void findComponents();
};

void TriangleSurface::Impl::findComponents() {
  component.assign(mesh.number_of_faces(), 0);
  componentCount = 0;
  std::vector<char> visited(mesh.number_of_faces(), 0);
  for (auto f : mesh.faces()) {
    if (visited[f]) continue;
    std::vector<Mesh::Face_index> stack{f};
    visited[f] = 1;
    while (!stack.empty()) {
      const auto g = stack.back();
      stack.pop_back();
      component[g] = componentCount;
      for (auto h : CGAL::halfedges_around_face(mesh.halfedge(g), mesh)) {
        const auto n = mesh.face(mesh.opposite(h));
        if (n != Mesh::null_face() && !visited[n]) {
          visited[n] = 1;
          stack.push_back(n);
        }
      }
    }
    ++componentCount;
  }
}

TriangleSurface::TriangleSurface() : impl_(std::make_unique<Impl>()) {}
TriangleSurface::~TriangleSurface() = default;

namespace {

std::string where(const KPoint& p) {
  std::ostringstream out;
  out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return out.str();
}

}  // namespace

std::shared_ptr<TriangleSurface> TriangleSurface::fromFile(const std::string& path, const std::string& name) {
  const std::string what = "input '" + name + "' (file '" + path + "')";
  TriangleSoup soup = readTriangleSurfaceFile(path, what);
  return validated(std::move(soup.points), soup.triangles, name, what,
                   [](std::size_t t) { return "triangle " + std::to_string(t + 1) + " of the file (counting from 1)"; });
}

std::shared_ptr<TriangleSurface> TriangleSurface::fromTriangles(std::vector<Point3> points,
                                                                const std::vector<std::array<int64_t, 3>>& triangles,
                                                                const std::string& name) {
  const std::string what = "input '" + name + "' (triangle surface)";
  if (triangles.empty()) throw InputError(what + " is empty: give at least the triangles of one closed surface");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!std::isfinite(points[i][0]) || !std::isfinite(points[i][1]) || !std::isfinite(points[i][2]))
      throw InputError(what + ": points[" + std::to_string(i) +
                       "] has a coordinate that is not a finite number: fix the points");
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int64_t v : triangles[t])
      if (v < 0 || v >= static_cast<int64_t>(points.size()))
        throw InputError(what + ": triangles[" + std::to_string(t) + "] refers to point " + std::to_string(v) +
                         ", but there are " + std::to_string(points.size()) + " points (indices count from 0)");
  return validated(std::move(points), triangles, name, what,
                   [](std::size_t t) { return "triangles[" + std::to_string(t) + "]"; });
}

namespace {

// The two triangles using an undirected edge, and whether each runs along it (a -> b, a < b).
struct EdgeUse {
  std::size_t count = 0;
  std::size_t triangle[2] = {0, 0};
  bool forward[2] = {false, false};
};

}  // namespace

std::shared_ptr<TriangleSurface> TriangleSurface::validated(std::vector<Point3> corners,
                                                            const std::vector<std::array<int64_t, 3>>& input,
                                                            const std::string& name, const std::string& what,
                                                            const std::function<std::string(std::size_t)>& triangleName) {
  std::vector<KPoint> points;
  points.reserve(corners.size());
  for (const Point3& p : corners) points.emplace_back(p[0], p[1], p[2]);
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(input.size());
  for (const auto& t : input) polygons.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
  // STL repeats every vertex per triangle: merge them so the triangles share edges.
  PMP::merge_duplicate_points_in_polygon_soup(points, polygons);
  // Triangles that collapsed onto an edge or a point (merged corners) bound nothing. The
  // survivors keep their input index for messages.
  std::vector<std::size_t> inputIndex;
  {
    std::vector<std::vector<std::size_t>> kept;
    for (std::size_t i = 0; i < polygons.size(); ++i) {
      const auto& t = polygons[i];
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      kept.push_back(t);
      inputIndex.push_back(i);
    }
    polygons.swap(kept);
  }
  if (polygons.empty()) throw InputError(what + " has only degenerate triangles: export it again");
  auto describeTriangle = [&](std::size_t t) {
    const auto& p = polygons[t];
    return triangleName(inputIndex[t]) + " with corners " + where(points[p[0]]) + ", " + where(points[p[1]]) + ", " +
           where(points[p[2]]);
  };

  // Edge use, read straight off the triangles: holes, non-manifold edges and local
  // orientation flips are named before CGAL's soup repair could hide or refuse them.
  std::map<std::pair<std::size_t, std::size_t>, EdgeUse> edges;
  for (std::size_t t = 0; t < polygons.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = polygons[t][k], b = polygons[t][(k + 1) % 3];
      EdgeUse& use = edges[{std::min(a, b), std::max(a, b)}];
      if (use.count < 2) {
        use.triangle[use.count] = t;
        use.forward[use.count] = a < b;
      }
      ++use.count;
    }
  std::size_t borderEdges = 0;
  for (const auto& [edge, use] : edges) {
    if (use.count > 2)
      throw InputError(what + " is not a manifold surface: the edge from " + where(points[edge.first]) + " to " +
                       where(points[edge.second]) + " is shared by " + std::to_string(use.count) +
                       " triangles; repair it (e.g. MeshLab, FreeCAD Mesh > Analyze > Evaluate and repair)");
    if (use.count == 1) ++borderEdges;
  }
  if (borderEdges > 0)
    throw InputError(what + " is not closed: it has holes bounded by " + std::to_string(borderEdges) +
                     " border edges; fill the holes (FreeCAD Mesh > Analyze > Evaluate and repair)");
  // Orientation: neighbours must run along their shared edge in opposite directions. Walking
  // each connected piece from its first triangle splits it into the triangles agreeing with
  // that one and those against it; the smaller group is what was flipped. A surface that is
  // consistently inward (a whole file written inside out) is turned round silently below.
  {
    std::vector<std::vector<std::pair<std::size_t, bool>>> neighbours(polygons.size());  // (other, same direction)
    for (const auto& [edge, use] : edges)
      if (use.count == 2) {
        const bool clash = use.forward[0] == use.forward[1];
        neighbours[use.triangle[0]].push_back({use.triangle[1], clash});
        neighbours[use.triangle[1]].push_back({use.triangle[0], clash});
      }
    std::vector<int> side(polygons.size(), -1);
    for (std::size_t start = 0; start < polygons.size(); ++start) {
      if (side[start] >= 0) continue;
      std::vector<std::size_t> piece{start}, stack{start};
      side[start] = 0;
      bool nonOrientable = false;
      while (!stack.empty()) {
        const std::size_t t = stack.back();
        stack.pop_back();
        for (const auto& [n, clash] : neighbours[t]) {
          const int expected = clash ? 1 - side[t] : side[t];
          if (side[n] < 0) {
            side[n] = expected;
            piece.push_back(n);
            stack.push_back(n);
          } else if (side[n] != expected) {
            nonOrientable = true;
          }
        }
      }
      if (nonOrientable)
        throw InputError(what + " is not orientable (a one-sided surface such as a Moebius strip, near " +
                         describeTriangle(start) + "): it bounds no solid; repair it");
      std::vector<std::size_t> against;
      for (std::size_t t : piece)
        if (side[t] == 1) against.push_back(t);
      if (against.empty()) continue;
      if (2 * against.size() > piece.size()) {
        against.clear();
        for (std::size_t t : piece)
          if (side[t] == 0) against.push_back(t);
      }
      std::sort(against.begin(), against.end());
      throw InputError(what + " has " + std::to_string(against.size()) +
                       (against.size() == 1 ? " triangle oriented against its neighbours ("
                                            : " triangles oriented against their neighbours (first: ") +
                       describeTriangle(against.front()) +
                       "): reverse the corner order of " + (against.size() == 1 ? "that triangle" : "those triangles") +
                       " (FreeCAD Mesh > Analyze > Evaluate and repair > Orientation)");
    }
  }

  auto surface = std::shared_ptr<TriangleSurface>(new TriangleSurface());
  Impl& m = *surface->impl_;
  m.name = name;
  // Edges are now manifold and consistently oriented; what orient_polygon_soup still refuses
  // are surfaces touching at a single vertex.
  if (!PMP::orient_polygon_soup(points, polygons))
    throw InputError(what + " is not a manifold surface (surfaces touching at a vertex): repair it (e.g. MeshLab, "
                     "FreeCAD Mesh > Analyze > Evaluate and repair)");
  PMP::polygon_soup_to_polygon_mesh(points, polygons, m.mesh);
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> crossing;
  PMP::self_intersections(m.mesh, std::back_inserter(crossing));
  if (!crossing.empty()) {
    const auto h = m.mesh.halfedge(crossing.front().first);
    throw InputError(what + " intersects itself (" + std::to_string(crossing.size()) +
                     " pairs of triangles, first near " + where(m.mesh.point(m.mesh.target(h))) +
                     "): repair it so the surface bounds one solid");
  }
  if (!PMP::is_outward_oriented(m.mesh)) PMP::reverse_face_orientations(m.mesh);

  for (auto v : m.mesh.vertices()) {
    const KPoint& p = m.mesh.point(v);
    m.box.add(Point3{p.x(), p.y(), p.z()});
  }
  m.volume = CGAL::to_double(PMP::volume(m.mesh));
  if (!(m.volume > 0)) throw InputError(what + " encloses no volume: give a closed surface around a solid");
  m.tree = std::make_unique<Tree>(faces(m.mesh).first, faces(m.mesh).second, m.mesh);
  m.tree->accelerate_distance_queries();  // built now, so that const queries never build
  m.side = std::make_unique<Side>(*m.tree);
  m.findComponents();
  return surface;
}

const std::string& TriangleSurface::name() const { return impl_->name; }
Bbox TriangleSurface::bbox() const { return impl_->box; }
double TriangleSurface::volume() const { return impl_->volume; }
size_t TriangleSurface::triangleCount() const { return impl_->mesh.number_of_faces(); }

void TriangleSurface::outwardTriangles(std::vector<Point3>& points,
                                       std::vector<std::array<int64_t, 3>>& triangles) const {
  const Mesh& mesh = impl_->mesh;
  std::vector<int64_t> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), -1);
  points.clear();
  triangles.clear();
  for (auto v : mesh.vertices()) {
    index[v] = static_cast<int64_t>(points.size());
    const KPoint& p = mesh.point(v);
    points.push_back({p.x(), p.y(), p.z()});
  }
  for (auto f : mesh.faces()) {
    std::array<int64_t, 3> corners{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      if (k < 3) corners[k++] = index[v];
    triangles.push_back(corners);
  }
}

bool TriangleSurface::inside(const Point3& p) const {
  if (!isFinite(p)) return false;  // CGAL's exact predicates would convert its NaN (SIGFPE)
  return (*impl_->side)(KPoint(p[0], p[1], p[2])) != CGAL::ON_UNBOUNDED_SIDE;
}

BoundaryProjection TriangleSurface::project(const Point3& p) const {
  if (!isFinite(p)) return {};  // CGAL's exact comparisons would convert its NaN (SIGFPE)
  const KPoint q(p[0], p[1], p[2]);
  const auto [closest, face] = impl_->tree->closest_point_and_primitive(q);
  BoundaryProjection r;
  r.point = {closest.x(), closest.y(), closest.z()};
  r.patch = static_cast<int>(face);
  r.distance = std::sqrt(CGAL::to_double(CGAL::squared_distance(q, closest)));
  return r;
}

std::vector<BoundarySample> TriangleSurface::boundarySamples(double spacing) const {
  // Triangle centroids, thinned to about `spacing` apart by a grid; every connected component
  // keeps its first triangle, so none is missed.
  const Mesh& mesh = impl_->mesh;
  std::vector<BoundarySample> samples;
  std::set<std::array<long long, 3>> used;
  const std::vector<std::size_t>& component = impl_->component;
  std::vector<char> componentSeen(impl_->componentCount, 0);
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    const KPoint a = mesh.point(mesh.source(h)), b = mesh.point(mesh.target(h)),
                 c = mesh.point(mesh.target(mesh.next(h)));
    const Point3 centroid{(a.x() + b.x() + c.x()) / 3, (a.y() + b.y() + c.y()) / 3, (a.z() + b.z() + c.z()) / 3};
    const auto n = CGAL::cross_product(b - a, c - a);
    const double len = std::sqrt(CGAL::to_double(n.squared_length()));
    if (len <= 0) continue;
    const std::array<long long, 3> cell{static_cast<long long>(std::floor(centroid[0] / spacing)),
                                        static_cast<long long>(std::floor(centroid[1] / spacing)),
                                        static_cast<long long>(std::floor(centroid[2] / spacing))};
    const bool first = !componentSeen[component[f]];
    if (!used.insert(cell).second && !first) continue;
    componentSeen[component[f]] = 1;
    samples.push_back({centroid, {n.x() / len, n.y() / len, n.z() / len}, static_cast<int>(f)});
  }
  return samples;
}

}  // namespace oraclemesh

namespace oraclemesh {

std::vector<BoundaryCrossing> TriangleSurface::crossings(const Point3& a, const Point3& b) const {
  const Impl& m = *impl_;
  std::vector<BoundaryCrossing> result;
  if (!isFinite(a) || !isFinite(b)) return result;
  const Point3 d = b - a;
  const double dd = dot(d, d);
  if (dd == 0.0) return result;
  const double length = std::sqrt(dd);
  const KPoint ka(a[0], a[1], a[2]), kb(b[0], b[1], b[2]);
  using Hit = boost::optional<Traits::Intersection_and_primitive_id<Kernel::Segment_3>::Type>;
  std::vector<Hit> raw;
  m.tree->all_intersections(Kernel::Segment_3(ka, kb), std::back_inserter(raw));
  if (raw.empty()) return result;

  // One record per triangle hit: the parameter range (a point, or the overlap of a segment
  // lying in the triangle's plane) and the side the segment goes to.
  struct TriangleHit {
    double t0, t1;
    int sign;  // sign of (outward normal . direction); 0 when the segment lies in the plane
    std::size_t component;
  };
  auto parameter = [&](const KPoint& p) {
    return std::clamp(dot(Point3{p.x(), p.y(), p.z()} - a, d) / dd, 0.0, 1.0);
  };
  std::vector<TriangleHit> hits;
  for (const Hit& hit : raw) {
    const Mesh::Face_index face = hit->second;
    TriangleHit h{0, 0, 0, m.component[face]};
    if (const KPoint* p = boost::get<KPoint>(&hit->first)) {
      h.t0 = h.t1 = parameter(*p);
      const auto he = m.mesh.halfedge(face);
      const KPoint& p0 = m.mesh.point(m.mesh.source(he));
      const KPoint& p1 = m.mesh.point(m.mesh.target(he));
      const KPoint& p2 = m.mesh.point(m.mesh.target(m.mesh.next(he)));
      const double s = CGAL::to_double(CGAL::cross_product(p1 - p0, p2 - p0) * Kernel::Vector_3(d[0], d[1], d[2]));
      h.sign = (s > 0) - (s < 0);
    } else if (const Kernel::Segment_3* overlap = boost::get<Kernel::Segment_3>(&hit->first)) {
      h.t0 = parameter(overlap->source());
      h.t1 = parameter(overlap->target());
      if (h.t0 > h.t1) std::swap(h.t0, h.t1);
    } else {
      continue;
    }
    hits.push_back(h);
  }
  std::sort(hits.begin(), hits.end(), [](const TriangleHit& x, const TriangleHit& y) { return x.t0 < y.t0; });

  // Hits closer than the tolerance are one place on the surface: the triangles around an
  // edge or a vertex the segment passes through.
  const double mergeT = 1e-10 * std::max(m.box.diagonal(), length) / length;
  struct Cluster {
    double t0, t1;
    std::vector<const TriangleHit*> hits;
  };
  std::vector<Cluster> clusters;
  for (const TriangleHit& h : hits) {
    if (clusters.empty() || h.t0 > clusters.back().t1 + mergeT)
      clusters.push_back({h.t0, h.t1, {}});
    clusters.back().t1 = std::max(clusters.back().t1, h.t1);
    clusters.back().hits.push_back(&h);
  }
  auto at = [&](double t) { return a + t * d; };
  for (size_t i = 0; i < clusters.size(); ++i) {
    const Cluster& c = clusters[i];
    BoundaryCrossing crossing;
    crossing.patch = static_cast<int>(c.hits.front()->component);
    if (c.hits.size() == 1 && c.hits.front()->sign != 0) {
      // Through the interior of one triangle: the normal tells the side.
      crossing.entering = c.hits.front()->sign < 0;
    } else {
      // Through an edge or a vertex, or along the surface: whether it crosses or only
      // touches is read from the sides of the surface between this place and its neighbours.
      const double before = 0.5 * ((i == 0 ? 0.0 : clusters[i - 1].t1) + c.t0);
      const double after = 0.5 * (c.t1 + (i + 1 == clusters.size() ? 1.0 : clusters[i + 1].t0));
      const bool insideBefore = inside(at(before)), insideAfter = inside(at(after));
      if (insideBefore == insideAfter) continue;
      crossing.entering = insideAfter;
    }
    crossing.t = 0.5 * (c.t0 + c.t1);
    crossing.point = at(crossing.t);
    result.push_back(crossing);
  }
  return result;
}

}  // namespace oraclemesh
