#include "sizing/GeometrySizes.h"

// CGAL before OpenCASCADE: OpenCASCADE defines a macro Handle.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRep_Tool.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <Poly_Triangulation.hxx>
#include <Standard_Failure.hxx>
#include <TopLoc_Location.hxx>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>

#include "RunControl.h"
#include "domain/BrepSolid.h"
#include "domain/BrepTopology.h"
#include "domain/OpenCascadeWork.h"
#include "features/BrepSharpEdges.h"
#include "sizing/DiscreteSurface.h"
#include "sizing/RayFirstHit.h"
#include "sizing/TriangleSpread.h"

namespace oraclemesh {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

constexpr double kPi = 3.14159265358979323846;

// The rays' reach beyond the distance that still asks for less than the cap, relative: the ray
// parameter and the distance measured from the hit round differently.
constexpr double kReachMargin = 1e-6;

// The sharp angle a discrete surface's curvature uses when the job asks for no sharp edges
// (the job's default sharp angle).
constexpr double kDiscreteSharpAngleDeg = 30;

Point3 toPoint3(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }

// One face triangle in model coordinates, its outward unit normal and area, the face it
// belongs to and its corners' surface parameters (when the triangulation has them); for a
// discrete surface, the triangle itself (face -1).
struct FaceTriangle {
  Point3 corners[3];
  gp_Pnt2d uv[3];
  bool hasUv = false;
  int face = -1;
  Point3 normal;
  double area = 0;
};

// Sets t's unit normal and area from its corners; false for a degenerate triangle.
bool withNormalAndArea(FaceTriangle& t) {
  const Point3 normal = cross(t.corners[1] - t.corners[0], t.corners[2] - t.corners[0]);
  const double len = norm(normal);
  if (!(len > 0)) return false;
  t.normal = (1 / len) * normal;
  t.area = len / 2;
  return true;
}

// The triangles of every face of `solid` (outward by the face's orientation); faces without a
// triangulation add none.
std::vector<FaceTriangle> faceTriangles(const BrepTopology& solid) {
  std::vector<FaceTriangle> out;
  for (int f = 0; f < solid.faceCount(); ++f) {
    const TopoDS_Face& face = solid.face(f);
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    if (tri.IsNull()) continue;
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (int t = 1; t <= tri->NbTriangles(); ++t) {
      int n[3];
      tri->Triangle(t).Get(n[0], n[1], n[2]);
      if (reversed) std::swap(n[1], n[2]);
      FaceTriangle ft;
      ft.face = f;
      ft.hasUv = tri->HasUVNodes();
      for (int k = 0; k < 3; ++k) {
        ft.corners[k] = toPoint3(tri->Node(n[k]).Transformed(loc));
        if (ft.hasUv) ft.uv[k] = tri->UVNode(n[k]);
      }
      if (withNormalAndArea(ft)) out.push_back(ft);
    }
  }
  return out;
}

// The triangles of a discrete surface (face -1, no uv); degenerate ones add none. `kept`
// gets the index in `surface` of each.
std::vector<FaceTriangle> faceTriangles(const DiscreteSurface& surface, std::vector<size_t>& kept) {
  std::vector<FaceTriangle> out;
  for (size_t i = 0; i < surface.triangles.size(); ++i) {
    FaceTriangle ft;
    for (int k = 0; k < 3; ++k) ft.corners[k] = surface.points[surface.triangles[i][k]];
    if (!withNormalAndArea(ft)) continue;
    out.push_back(ft);
    kept.push_back(i);
  }
  return out;
}

Point3 centroid(const FaceTriangle& t) { return (1.0 / 3) * (t.corners[0] + t.corners[1] + t.corners[2]); }

// The weights of corners 0 and 1 of the point of t's plane nearest p (corner 2 has the rest).
std::array<double, 2> barycentric(const FaceTriangle& t, const Point3& p) {
  const Point3 e1 = t.corners[1] - t.corners[0], e2 = t.corners[2] - t.corners[0], d = p - t.corners[0];
  const double a = dot(e1, e1), b = dot(e1, e2), c = dot(e2, e2), f = dot(d, e1), g = dot(d, e2);
  const double det = a * c - b * b;
  if (!(det > 0)) return {1.0 / 3, 1.0 / 3};
  const double w1 = (c * f - b * g) / det, w2 = (a * g - b * f) / det;
  return {1 - w1 - w2, w1};
}

// The exact face's unit normal at the point of triangle t nearest p, on t's side; false where
// the triangle has no uv or the normal is not defined.
bool exactNormal(const BRepAdaptor_Surface& surface, const FaceTriangle& t, const Point3& p, Point3& normal) {
  if (!t.hasUv) return false;
  const std::array<double, 2> w = barycentric(t, p);
  const double u = w[0] * t.uv[0].X() + w[1] * t.uv[1].X() + (1 - w[0] - w[1]) * t.uv[2].X();
  const double v = w[0] * t.uv[0].Y() + w[1] * t.uv[1].Y() + (1 - w[0] - w[1]) * t.uv[2].Y();
  BRepLProp_SLProps props(surface, u, v, 1, 1e-9);
  if (!props.IsNormalDefined()) return false;
  const gp_Dir d = props.Normal();
  normal = {d.X(), d.Y(), d.Z()};
  if (dot(normal, t.normal) < 0) normal = -1.0 * normal;
  return true;
}

// Faces across a wall or a gap face each other within this angle (their exact normals: a
// tessellation's can be off by half its 0.5 rad angular deflection): a plate, a clearance
// fit. Faces meeting at a larger angle leave a wedge (a chamfer, a thread's flanks), which
// narrows to nothing where they meet and would ask for sizes without bound: Rule Set T treats
// it as the small input angle it is.
constexpr double kFacingWithinDeg = 15;

// Whether unit normals a and b (outward, each on its own face) face each other within
// kFacingWithinDeg.
bool facing(const Point3& a, const Point3& b) { return dot(a, b) < -std::cos(kFacingWithinDeg * kPi / 180); }

class FaceSampler;

// Whether the faces at p (on triangle a of sampler sa) and at q (on triangle b of sb) face
// each other, as a wall's or a gap's two sides do, not as a wedge's; true where a normal is
// unknown. Opposite triangles need no exact normals.
bool faceEachOther(const FaceSampler& sa, const FaceTriangle& a, const Point3& p, const FaceSampler& sb,
                   const FaceTriangle& b, const Point3& q);

// The ball radius of triangles with N of their edges around a full circle of radius 1.
double sizePerRadius(int segmentsPerCircle) { return 2 * std::sin(kPi / segmentsPerCircle) / std::sqrt(3.0); }

// Short edges: a sharp edge gets at least two segments: the size along an edge of length L is
// at most L / 2 (edge sizes are the size, kEdgeSizePerSize).
void addShortEdgeSamples(const BrepTopology& solid, double sharpAngleDeg, std::vector<SizeSample>& out,
                         const RunControl& control) {
  const double cosSharp = std::cos(sharpAngleDeg * kPi / 180);
  for (int e = 0; e < solid.edgeCount(); ++e) {
    control.checkpoint();
    const TopoDS_Edge& edge = solid.edge(e);
    if (BRep_Tool::Degenerated(edge)) continue;
    const std::vector<int>& faces = solid.facesOfEdge(e);
    BRepAdaptor_Curve curve(edge);
    const double u0 = curve.FirstParameter(), u1 = curve.LastParameter(), um = 0.5 * (u0 + u1);
    if (faces.size() == 2) {
      gp_Vec n0, n1;
      if (!outwardNormalAlongEdge(edge, solid.face(faces[0]), um, n0) ||
          !outwardNormalAlongEdge(edge, solid.face(faces[1]), um, n1) || n0.Dot(n1) > cosSharp)
        continue;  // smooth (or undecidable): the mesh need not follow the edge
    } else if (faces.size() == 1 && BRep_Tool::IsClosed(edge, solid.face(faces[0]))) {
      continue;  // a seam
    }
    const double length = GCPnts_AbscissaPoint::Length(curve);
    if (!(length > 0)) continue;
    for (double u : {u0, um, u1}) out.push_back({toPoint3(curve.Value(u)), 0.5 * length, SizeReason::ShortEdge});
  }
}

// Samples over every face triangle of one solid, close enough to each other that the graded
// field between them stays near what they ask for: curvature (the tightest principal radius of
// the face at the point) and thickness (from the point inwards along the triangle's normal, the
// distance to the solid's own opposite face: a wall of thickness t asks for t /
// sizes_per_thickness). Other inputs do not count for the thickness: where parts touch, their
// faces lie within the CAD tolerance of each other, which is no wall (gaps between parts are
// GapRays' below).
class FaceSampler {
 public:
  // Measures the sizes each triangle asks for at its corners and centre (what the estimate
  // and the dense sampling need), capped at `cap`.
  // Without a fineness, the triangles ask for the cap alone (only gaps lower it).
  FaceSampler(const BrepTopology& solid, const FinenessPreset* fineness, double diagonal, double cap,
              const RunControl& control)
      : topology_(&solid),
        name_(solid.name()),
        triangles_(faceTriangles(solid)),
        fromShape_(fineness != nullptr),
        sizeOverRadius_(fineness ? sizePerRadius(fineness->segments_per_circle) : 0),
        sizesPerThickness_(fineness ? fineness->sizes_per_thickness : 0),
        offset_(1e-7 * diagonal),
        cap_(cap) {
    surfaces_.resize(solid.faceCount());
    planar_.assign(solid.faceCount(), false);
    measure(cap, control);
  }

  // The same over a discrete surface (an input without exact faces named `name`): the
  // curvature is the surface's own at its triangles' corners (sizing/DiscreteSurface.h), interpolated
  // across each triangle, and asks for nothing under the surface's resolution.
  FaceSampler(const std::string& name, const DiscreteSurface& surface, double sharpAngleDeg,
              const FinenessPreset* fineness, double diagonal, double cap, const RunControl& control)
      : name_(name),
        fromShape_(fineness != nullptr),
        sizeOverRadius_(fineness ? sizePerRadius(fineness->segments_per_circle) : 0),
        sizesPerThickness_(fineness ? fineness->sizes_per_thickness : 0),
        offset_(1e-7 * diagonal),
        cap_(cap),
        resolution_(surface.resolution) {
    std::vector<size_t> kept;
    triangles_ = faceTriangles(surface, kept);
    if (fromShape_) {
      const std::vector<std::array<double, 3>> curvatures = cornerCurvatures(surface, sharpAngleDeg);
      for (size_t i : kept) cornerCurvatures_.push_back(curvatures[i]);
    }
    measure(cap, control);
  }

  // The solid's faces and edges; nullptr for a discrete surface.
  const BrepTopology* topology() const { return topology_; }
  const std::string& name() const { return name_; }
  const std::vector<FaceTriangle>& triangles() const { return triangles_; }

  // The unit normal at p of the face under triangle t: the exact face's (nullopt where it
  // is unknown), a discrete surface's triangle's own.
  std::optional<Point3> normalAt(const FaceTriangle& t, const Point3& p) const {
    if (!topology_) return t.normal;
    Point3 n;
    if (exactNormal(surface(t.face), t, p, n)) return n;
    return std::nullopt;
  }

 private:
  // The sizes each triangle asks for (curvature, thickness), the tree the thickness rays
  // need, and the surface vertex estimate.
  void measure(double cap, const RunControl& control) {
    for (const FaceTriangle& t : triangles_)
      cgalTriangles_.emplace_back(K::Point_3(t.corners[0][0], t.corners[0][1], t.corners[0][2]),
                                  K::Point_3(t.corners[1][0], t.corners[1][1], t.corners[1][2]),
                                  K::Point_3(t.corners[2][0], t.corners[2][1], t.corners[2][2]));
    if (!cgalTriangles_.empty()) tree_ = std::make_unique<TriangleTree>(cgalTriangles_.begin(), cgalTriangles_.end());
    local_.resize(triangles_.size());
    smallest_.size = cap;
    for (size_t i = 0; i < triangles_.size(); ++i) {
      if (i % 1024 == 0) control.checkpoint();
      const FaceTriangle& t = triangles_[i];
      double local = cap;
      SizeReason reason = SizeReason::Curvature;
      if (fromShape_) {
        for (int k = 0; k < 3; ++k) local = std::min(local, curvatureSize(i, {k == 0 ? 1.0 : 0, k == 1 ? 1.0 : 0}));
        const double thickness = thicknessSize(t, i, centroid(t));
        if (thickness < local) {
          local = thickness;
          reason = SizeReason::Thickness;
        }
      }
      local_[i] = local;
      // A surface mesh of ball radius s has triangles of about s^2 and half as many vertices
      // as triangles: 1.3 s^2 of area per vertex errs on the low side.
      surfaceVertices_ += t.area / (1.3 * local * local);
      if (local < smallest_.size) smallest_ = {centroid(t), local, reason};
    }
    shapeSizes_ = local_;
  }

 public:
  // Lowers each triangle's size to what the gap outside its centre asks for (`gapSize`:
  // triangle, point -> size, infinity for none), so the sampling and the estimate see it.
  template <class GapSize>
  void lowerToGaps(const GapSize& gapSize, const RunControl& control) {
    for (size_t i = 0; i < triangles_.size(); ++i) {
      if (i % 1024 == 0) control.checkpoint();
      const FaceTriangle& t = triangles_[i];
      const double gap = gapSize(t, centroid(t));
      if (!(gap < local_[i])) continue;
      surfaceVertices_ += t.area / (1.3 * gap * gap) - t.area / (1.3 * local_[i] * local_[i]);
      local_[i] = gap;
      if (gap < smallest_.size) smallest_ = {centroid(t), gap, SizeReason::Gap};
    }
  }
  // The surface vertices the sizes asked for would make on this solid's faces (faces a higher
  // input hides count too: an estimate for orders of magnitude).
  double surfaceVertices() const { return surfaceVertices_; }
  const SizeSample& smallest() const { return smallest_; }
  // The size triangle `index` asks for from the solid's own shape (curvature, thickness; the
  // cap without a fineness), before any gap lowers it.
  double shapeSize(size_t index) const { return shapeSizes_[index]; }
  // `face`'s exact surface, built when first needed.
  const BRepAdaptor_Surface& surface(int face) const {
    auto& s = surfaces_[face];
    if (!s) {
      s = std::make_unique<BRepAdaptor_Surface>(topology_->face(face), false);
      planar_[face] = s->GetType() == GeomAbs_Plane;
    }
    return *s;
  }

  // Curvature and thickness samples (into `shape`, with a fineness) and gap samples (into
  // `gaps`) spaced at the sizes each triangle asks for; `gapSize` (triangle, point): the size a
  // gap outside the solid asks for there, infinity for none.
  template <class GapSize>
  void addSamples(std::vector<SizeSample>& shape, std::vector<SizeSample>& gaps, const GapSize& gapSize,
                  const RunControl& control) {
    for (size_t i = 0; i < triangles_.size(); ++i) {
      if (i % 1024 == 0) control.checkpoint();
      const FaceTriangle& t = triangles_[i];
      for (const std::array<double, 2>& w : spreadOverTriangle(t.corners, kSpacingPerSize * local_[i], kMaxPoints)) {
        const Point3 p = w[0] * t.corners[0] + w[1] * t.corners[1] + (1 - w[0] - w[1]) * t.corners[2];
        if (fromShape_) {
          const double curvature = curvatureSize(i, w);
          if (std::isfinite(curvature)) shape.push_back({p, curvature, SizeReason::Curvature});
          const double thickness = thicknessSize(t, i, p);
          if (std::isfinite(thickness)) shape.push_back({p, thickness, SizeReason::Thickness});
        }
        const double gap = gapSize(t, p);
        if (std::isfinite(gap)) gaps.push_back({p, gap, SizeReason::Gap});
      }
    }
  }

 private:
  // Only reached by a triangle a thousand sizes long, on a model the vertex limit allows.
  static constexpr size_t kMaxPoints = 1000 * 1001 / 2;
  // Samples at most this many sizes apart: halfway between two, the graded field is at most
  // grading * spacing / 2 = 0.2 of the size above what they ask for ("moderate").
  static constexpr double kSpacingPerSize = 1.33;

  // Infinity on planes and where the curvature is not defined.
  double curvatureSize(size_t index, std::array<double, 2> w) const {
    const FaceTriangle& t = triangles_[index];
    if (!topology_) {
      const std::array<double, 3>& c = cornerCurvatures_[index];
      const double k = w[0] * c[0] + w[1] * c[1] + (1 - w[0] - w[1]) * c[2];
      return k > 0 && std::isfinite(k) ? std::max(sizeOverRadius_ / k, resolution_)
                                       : std::numeric_limits<double>::infinity();
    }
    if (!t.hasUv) return std::numeric_limits<double>::infinity();
    const BRepAdaptor_Surface& surface = this->surface(t.face);
    if (planar_[t.face]) return std::numeric_limits<double>::infinity();
    const double u = w[0] * t.uv[0].X() + w[1] * t.uv[1].X() + (1 - w[0] - w[1]) * t.uv[2].X();
    const double v = w[0] * t.uv[0].Y() + w[1] * t.uv[1].Y() + (1 - w[0] - w[1]) * t.uv[2].Y();
    BRepLProp_SLProps props(surface, u, v, 2, 1e-9);
    if (!props.IsCurvatureDefined()) return std::numeric_limits<double>::infinity();
    const double k = std::max(std::abs(props.MaxCurvature()), std::abs(props.MinCurvature()));
    return k > 0 && std::isfinite(k) ? sizeOverRadius_ / k : std::numeric_limits<double>::infinity();
  }

  // Infinity where the ray finds no wall across. The ray leaves the solid through the wall's
  // other side, whose outward normal points along the ray; a hit on a face at a grazing angle
  // or facing back (a neighbouring triangle of a curved face, hit through rounding at a shared
  // edge) measures no wall.
  double thicknessSize(const FaceTriangle& t, size_t index, const Point3& p) const {
    if (!tree_) return std::numeric_limits<double>::infinity();
    const Point3 start = p - offset_ * t.normal;
    const K::Ray_3 ray(K::Point_3(start[0], start[1], start[2]), K::Vector_3(-t.normal[0], -t.normal[1], -t.normal[2]));
    // A wall thicker than this asks for more than the cap, which holds anyway.
    const RayFirstHit<TriangleTree> search(*tree_, ray, (1 + kReachMargin) * cap_ * sizesPerThickness_);
    const auto& hit = search.hit();
    if (!hit) return std::numeric_limits<double>::infinity();
    const K::Point_3* q = boost::get<K::Point_3>(&hit->first);
    if (!q) return std::numeric_limits<double>::infinity();  // the ray runs within a triangle
    const size_t j = static_cast<size_t>(hit->second - cgalTriangles_.cbegin());
    if (j == index || dot(triangles_[j].normal, t.normal) > -0.2) return std::numeric_limits<double>::infinity();
    const FaceTriangle& across = triangles_[j];
    if (!faceEachOther(*this, t, p, *this, across, Point3{q->x(), q->y(), q->z()}))
      return std::numeric_limits<double>::infinity();
    return (std::sqrt(CGAL::squared_distance(*q, ray.source())) + offset_) / sizesPerThickness_;
  }

  const BrepTopology* topology_ = nullptr;
  std::string name_;
  std::vector<FaceTriangle> triangles_;
  Triangles cgalTriangles_;
  std::unique_ptr<TriangleTree> tree_;
  // Per face, built when first needed.
  mutable std::vector<std::unique_ptr<BRepAdaptor_Surface>> surfaces_;
  mutable std::vector<bool> planar_;
  bool fromShape_;  // curvature and thickness count (a fineness is set)
  double sizeOverRadius_, sizesPerThickness_, offset_;
  double cap_;             // sizes at or above it are no samples (SizeField drops them)
  double resolution_ = 0;  // a discrete surface's: no curvature size below it
  std::vector<std::array<double, 3>> cornerCurvatures_;  // a discrete surface's, per triangle
  std::vector<double> local_;  // per triangle: the smallest size asked at its corners and centre
  std::vector<double> shapeSizes_;  // local_ before the gaps lowered it
  double surfaceVertices_ = 0;
  SizeSample smallest_;
};

bool faceEachOther(const FaceSampler& sa, const FaceTriangle& a, const Point3& p, const FaceSampler& sb,
                   const FaceTriangle& b, const Point3& q) {
  if (dot(a.normal, b.normal) < -0.9999) return true;
  const std::optional<Point3> na = sa.normalAt(a, p), nb = sb.normalAt(b, q);
  return !na || !nb || facing(*na, *nb);
}

// Gaps between inputs: from a face sample outwards along the normal to the first face of
// another input facing back. A gap of width w asks for w / sizesPerGap on both sides,
// so the faces' triangles are small enough that no tetrahedron reaches across (its
// circumcentre would lie in the gap, outside both parts). Inputs closer than the job's
// contact tolerance touch: no gap, they are bonded. The width is measured between the faces'
// triangles, and between the exact surfaces (projections on both inputs) where the
// triangles' deviation from them could decide which side of the tolerance it falls.
class GapRays {
  // Where two parts touch along a line (a wedge between a face and a chamfer, a cylinder on a
  // plane) the gap narrows to nothing and w / sizesPerGap with it: sizes stop at this fraction
  // of the largest cell size, so the part of such a wedge narrower than about that is bonded
  // (a contact line in a mesh always is, over an element or so) instead of being refined
  // without bound. A gap of presse_asm.step's narrowest, 0.075 mm under cells of 48 mm, is
  // above it.
  static constexpr double kGapSizePerCap = 1e-3;

 public:
  struct Gap {
    double size = std::numeric_limits<double>::infinity();  // infinity: no gap
    double width = 0;
    size_t other = 0;  // the sampler across the gap
    // A wedge beside a tangent contact, bonded (size infinity): the local size it was judged by.
    double bondedReach = 0;
  };

  // `deviations`: per sampler, how far its triangles may lie from its input's boundary.
  GapRays(const std::vector<FaceSampler>& samplers, const std::vector<const Source*>& sources,
          const std::vector<double>& deviations, double diagonal, double sizesPerGap, double cap,
          double contactTolerance)
      : samplers_(samplers),
        sources_(sources),
        deviations_(deviations),
        offset_(1e-7 * diagonal),
        contactTolerance_(contactTolerance),
        sizesPerGap_(sizesPerGap),
        cap_(cap) {
    for (size_t s = 0; s < samplers.size(); ++s)
      for (size_t i = 0; i < samplers[s].triangles().size(); ++i) {
        const FaceTriangle& t = samplers[s].triangles()[i];
        triangles_.emplace_back(K::Point_3(t.corners[0][0], t.corners[0][1], t.corners[0][2]),
                                K::Point_3(t.corners[1][0], t.corners[1][1], t.corners[1][2]),
                                K::Point_3(t.corners[2][0], t.corners[2][1], t.corners[2][2]));
        owners_.push_back({s, i});
      }
    if (samplers.size() > 1 && !triangles_.empty())
      tree_ = std::make_unique<TriangleTree>(triangles_.cbegin(), triangles_.cend());
  }

  // The gap outside sampler `owner`'s triangle `t` at p.
  Gap at(size_t owner, const FaceTriangle& t, const Point3& p) const {
    if (!tree_) return {};
    const Point3 start = p + offset_ * t.normal;
    const K::Ray_3 ray(K::Point_3(start[0], start[1], start[2]), K::Vector_3(t.normal[0], t.normal[1], t.normal[2]));
    // A gap wider than this asks for more than the cap (below): no gap.
    const RayFirstHit<TriangleTree> search(*tree_, ray, (1 + kReachMargin) * cap_ * sizesPerGap_);
    const auto& hit = search.hit();
    if (!hit) return {};
    const K::Point_3* q = boost::get<K::Point_3>(&hit->first);
    if (!q) return {};
    const auto [other, j] = owners_[static_cast<size_t>(hit->second - triangles_.cbegin())];
    const FaceTriangle& facing = samplers_[other].triangles()[j];
    if (other == owner || dot(facing.normal, t.normal) > -0.2) return {};
    const double along = std::sqrt(CGAL::squared_distance(*q, ray.source())) + offset_;
    if (!(along / sizesPerGap_ < cap_)) return {};  // the cap holds there
    // The triangles lie within their solids' deviations of the exact faces, so the width
    // between the faces is `along` give or take both: the exact projections (slow, and met
    // over every face where parts touch) decide only when that band straddles the tolerance.
    const double band = deviations_[owner] + deviations_[other];
    if (along + band <= contactTolerance_) return {};
    const Point3 hitPoint{q->x(), q->y(), q->z()};
    if (!faceEachOther(samplers_[owner], t, p, samplers_[other], facing, hitPoint))
      return {};
    const size_t index = static_cast<size_t>(&t - samplers_[owner].triangles().data());
    const double local = std::min(samplers_[owner].shapeSize(index), samplers_[other].shapeSize(j));
    if (closingWedge(owner, t, p, other, facing, hitPoint, along, local)) {
      Gap bonded;
      bonded.width = along;
      bonded.other = other;
      bonded.bondedReach = local;
      return bonded;
    }
    double width = along;
    if (!(along - band > contactTolerance_)) {
      // From each end of the ray, its solid's nearest boundary point to the other solid's
      // nearest: the smaller is the width. One end alone can land on another face of its solid
      // next to an edge (a sample on the bottom circle of a pin filling a hole lies a sagitta
      // inside the circle, on the pin's bottom face: a width of that sagitta).
      const Point3 onOwner = sources_[owner]->project(p).point;
      width = distance(onOwner, sources_[other]->project(onOwner).point);
      if (!(width > contactTolerance_)) return {};
      const Point3 onOther = sources_[other]->project(hitPoint).point;
      width = std::min(width, distance(onOther, sources_[owner]->project(onOther).point));
      if (!(width > contactTolerance_)) return {};
    }
    return {std::max(width / sizesPerGap_, kGapSizePerCap * cap_), width, other};
  }

 private:
  // Whether the gap of width `along` between p and q is a wedge beside a tangent contact that
  // the mesh bonds (BondedWedges.h): narrower than kWedgeBondPerSize of the local size, and
  // closing within kWedgeClosingPerSize of it (width over the sine of the angle between the
  // faces; a clearance between faces that face each other exactly never closes).
  bool closingWedge(size_t owner, const FaceTriangle& t, const Point3& p, size_t other, const FaceTriangle& facing,
                    const Point3& q, double along, double local) const {
    if (!(along < kWedgeBondPerSize * local)) return false;
    const std::optional<Point3> na = samplers_[owner].normalAt(t, p), nb = samplers_[other].normalAt(facing, q);
    if (!na || !nb) return false;
    return along <= norm(cross(*na, *nb)) * kWedgeClosingPerSize * local;
  }

  const std::vector<FaceSampler>& samplers_;
  const std::vector<const Source*>& sources_;
  Triangles triangles_;
  std::vector<std::pair<size_t, size_t>> owners_;  // per triangle: sampler, triangle there
  std::vector<double> deviations_;                 // per sampler: its triangles to its input, at most
  std::unique_ptr<TriangleTree> tree_;
  double offset_, contactTolerance_, sizesPerGap_, cap_;
};

}  // namespace

GeometrySizes geometrySizes(const HierarchicalOracle& oracle, const FinenessPreset* fineness, double sizesPerGap,
                            double sharpAngleDeg, double cap, double contactTolerance, double vertexLimit,
                            const RunControl& control) {
  GeometrySizes sizes;
  std::vector<FaceSampler> samplers;
  std::vector<const Source*> sources;  // per sampler
  std::vector<int> entries;            // per sampler: its oracle entry
  std::vector<double> deviations;      // per sampler: its triangles from its input's boundary
  // Where the job has no sharp edges, discrete surfaces still tell an edge from a curve.
  const double discreteSharpAngle = sharpAngleDeg > 0 ? sharpAngleDeg : kDiscreteSharpAngleDeg;
  const std::string* current = nullptr;  // the input being measured, for the message
  // OpenCASCADE's calls are marked for the hard deadline's watchdog; a discrete surface makes none.
  const auto openCascadeWork = [](const FaceSampler& sampler, std::optional<OpenCascadeWork>& scope) {
    if (sampler.topology()) scope.emplace(sampler.name());
  };
  try {
    double largest = -1;
    for (size_t e = 0; e < oracle.entries().size(); ++e) {
      const Source& source = *oracle.entries()[e].source;
      current = &source.name();
      if (const BrepTopology* solid = source.brepTopology()) {
        const OpenCascadeWork working(solid->name());
        samplers.emplace_back(*solid, fineness, oracle.diagonal(), cap, control);
        const auto* brep = dynamic_cast<const BrepSolid*>(&source);
        deviations.push_back(brep && brep->proxyInfo().usable ? brep->proxyInfo().deflection
                                                              : std::numeric_limits<double>::infinity());
      } else {
        const DiscreteSurface surface = discreteSurfaceOf(source, control);
        if (surface.triangles.empty()) continue;
        samplers.emplace_back(source.name(), surface, discreteSharpAngle, fineness, oracle.diagonal(), cap, control);
        deviations.push_back(surface.deviation);
      }
      sources.push_back(&source);
      entries.push_back(static_cast<int>(e));
    }
    const GapRays gaps(samplers, sources, deviations, oracle.diagonal(), sizesPerGap, cap, contactTolerance);
    std::map<std::pair<int, int>, PartGap> narrowest;  // per pair of entries
    for (size_t s = 0; s < samplers.size(); ++s) {
      current = &samplers[s].name();
      std::optional<OpenCascadeWork> working;
      openCascadeWork(samplers[s], working);
      samplers[s].lowerToGaps(
          [&](const FaceTriangle& t, const Point3& p) {
            const GapRays::Gap gap = gaps.at(s, t, p);
            if (!std::isfinite(gap.size)) return gap.size;
            const auto pair = std::minmax(entries[s], entries[gap.other]);
            auto [place, fresh] = narrowest.try_emplace(pair, PartGap{pair.first, pair.second, gap.width, p});
            if (!fresh && gap.width < place->second.width) place->second = {pair.first, pair.second, gap.width, p};
            return gap.size;
          },
          control);
      sizes.surface_vertices += samplers[s].surfaceVertices();
      if (samplers[s].surfaceVertices() > largest) {
        largest = samplers[s].surfaceVertices();
        sizes.largest_entry = entries[s];
        sizes.smallest = samplers[s].smallest();
      }
    }
    for (const auto& [pair, gap] : narrowest) sizes.gaps.push_back(gap);
    std::stable_sort(sizes.gaps.begin(), sizes.gaps.end(),
                     [](const PartGap& a, const PartGap& b) { return a.width < b.width; });
    // Sampling as densely as such sizes ask would itself take that many points.
    if (!(sizes.surface_vertices <= vertexLimit)) return sizes;
    for (size_t s = 0; s < samplers.size(); ++s) {
      FaceSampler& sampler = samplers[s];
      current = &sampler.name();
      std::optional<OpenCascadeWork> working;
      openCascadeWork(sampler, working);
      sampler.addSamples(
          sizes.samples, sizes.gap_samples,
          [&](const FaceTriangle& t, const Point3& p) {
            const GapRays::Gap gap = gaps.at(s, t, p);
            if (gap.bondedReach > 0) {
              const auto pair = std::minmax(entries[s], entries[gap.other]);
              sizes.bonded_wedges.push_back({p, gap.width, gap.bondedReach, pair.first, pair.second});
            }
            return gap.size;
          },
          control);
      if (fineness && sharpAngleDeg > 0 && sampler.topology())
        addShortEdgeSamples(*sampler.topology(), sharpAngleDeg, sizes.samples, control);
    }
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed while measuring the curvature of input '" + *current + "' (" +
                failure.GetMessageString() + "): check the solid with Part > Check geometry");
  }
  return sizes;
}

}  // namespace oraclemesh
