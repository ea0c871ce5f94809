#pragma once
// BrepSolid's state (internal to domain/brep and domain/BrepSolid.cpp): the indexed topology,
// the exact classifiers, the tessellation proxy and what the crossing search keeps per face
// and per proxy triangle. Its members are defined by job: index() in domain/BrepSolid.cpp;
// in domain/brep/: TessellationProxy.cpp (the proxy and its bands), ParametricDomain.cpp
// (chord reach, domainByTriangles), Classification.cpp (proxyTrusted, classifyExact),
// CandidateFaces.cpp (facesNearSegment), AnalyticCrossings.cpp, NewtonCrossings.cpp,
// Crossings.cpp (exactCrossings) and Projections.cpp (projectOnFace).
// CGAL comes before any OpenCASCADE header: OCCT defines a function-like macro `Handle`
// that breaks CGAL's templates (CGAL/Lazy.h) when they are parsed after it. Include this
// header before any OpenCASCADE header.
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include "domain/BrepSolid.h"

#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <Geom_Surface.hxx>
#include <IntCurvesFace_Intersector.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Ax3.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Torus.hxx>
#include <gp_XYZ.hxx>

#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "domain/brep/BoxTree.h"

namespace oraclemesh {

// The tessellation proxy's CGAL types.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using KPoint = Kernel::Point_3;
using ProxyMesh = CGAL::Surface_mesh<KPoint>;
using ProxyPrimitive = CGAL::AABB_face_graph_triangle_primitive<ProxyMesh>;
using ProxyTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, ProxyPrimitive>>;
using ProxySide = CGAL::Side_of_triangle_mesh<ProxyMesh, Kernel>;

struct BrepSolid::Impl {
  std::string name;
  TopoDS_Shape shape;
  Bbox box;
  double diagonal = 0;
  double volume = 0;
  double maxShapeTolerance = 0;  // largest vertex/edge/face tolerance of the model

  TopTools_IndexedMapOfShape faceMap, edgeMap;
  std::vector<TopoDS_Face> faces;
  std::vector<TopoDS_Edge> edges;
  std::vector<std::vector<int>> edgeFaces;

  // Exact classification: one BRepClass3d_SolidClassifier per solid and thread. Loading a
  // classifier builds per-face intersectors (costly), and an instance keeps mutable state
  // during Perform(), so instances are never shared between threads: each query leases
  // one from the pool of its solid (or loads a new one) and gives it back afterwards.
  struct ClassifierPool {
    TopoDS_Shape solid;
    Bbox box;
    mutable std::mutex mutex;
    mutable std::vector<std::unique_ptr<BRepClass3d_SolidClassifier>> idle;
  };
  std::vector<std::unique_ptr<ClassifierPool>> solids;
  double classifyTolerance = 0;

  // Tessellation proxy. The tree and the side-of-mesh functor are only read by queries
  // (the tree and its distance-query kd-tree are built eagerly below), so they are shared.
  ProxyMesh proxyMesh;
  std::vector<int> proxyFaceOfTriangle;  // B-rep face (0-based) of each proxy triangle
  std::vector<double> faceBand;          // per face: the proxy is trusted farther than this
  std::unique_ptr<ProxyTree> proxyTree;
  std::unique_ptr<ProxySide> proxySide;
  ProxyInfo proxy;
  std::vector<int> facesWithoutTriangles;  // always intersected exactly by crossings()
  std::vector<CGAL::Bbox_3> proxyTriangleBox;
  // crossings(): a face lies within its band of its own triangles except next to a curved
  // edge, where the face reaches beyond the edge's polygon by the polygon's sagitta (a hole
  // in a planar face). The candidate test widens each face's band by that much.
  std::vector<double> crossingBand;
  double maxCrossingBand = 0;
  // crossings(): what a Newton iteration on the exact surface needs from each proxy triangle
  // (same order as proxyFaceOfTriangle). `regular`: it has surface parameters and the
  // surface has a normal all over it that keeps one side (no pole, no fold). `tilt`: the
  // largest angle (radians) between the triangle's normal and the surface normals sampled
  // over it; a line steeper than 90 degrees minus that angle (and a margin) crosses the
  // surface patch over the triangle at most once.
  struct NewtonTriangle {
    std::array<gp_Pnt, 3> node;
    std::array<gp_Pnt2d, 3> uv;
    double tilt = 0;
    bool regular = false;
    // No node on the boundary of the face's triangulation (face edges, seams, poles): the
    // parametric triangle lies inside the face's domain, no classification needed.
    bool interior = false;
    // Edge k (node k to node k+1) bounds the face's kept triangles on one side only: a chord
    // of a face edge, of a seam, or of a gap left by triangles collapsed at a pole. Only
    // near such chords can the face's domain and its triangles' parametric union differ.
    std::array<bool, 3> boundaryEdge{};
    std::array<int, 3> corner{};  // node indices in the face's triangulation
    // For a boundary chord on a face edge: how far (in the parameters) the face's domain may
    // reach past it or fall short of it (the edge's parametric curve against the chord, with
    // margins, plus the edge's tolerance); negative where unknown (a gap at a pole), then the
    // 3D crossing band stands in.
    std::array<double, 3> chordReach{-1, -1, -1};
  };
  // Per face: periods of the parameters (0 when not periodic).
  std::vector<std::array<double, 2>> period;
  std::vector<NewtonTriangle> newtonTriangle;
  // crossings(): per face, how far the exact surface over a proxy triangle may be from it
  // (the measured deviation with its margin, plus the face's tolerance).
  std::vector<double> patchDeviation;
  // crossings(): faces on a plane, cylinder, cone, sphere or torus are intersected with the
  // segment's line in closed form; `kind` None sends a face to Newton iteration.
  struct AnalyticSurface {
    enum class Kind { None, Plane, Cylinder, Cone, Sphere, Torus } kind = Kind::None;
    gp_Ax3 frame;          // the surface's own frame (location applied)
    double radius = 0;     // cylinder, sphere; cone: at the frame's origin; torus: major
    double minorRadius = 0;
    double semiAngle = 0, tanAngle = 0, cosAngle = 1;  // cone half-angle (radians), its tangent and cosine
    gp_Torus torus;
    // Parameters (u, v) and a normal (not unit) of the point (x, y, z) of the surface, given
    // in the frame; false at a pole or apex (no normal, several parameters).
    bool parameters(double x, double y, double z, double tolerance, double& u, double& v, gp_XYZ& normal) const {
      const double radial = std::hypot(x, y);
      switch (kind) {
        case Kind::Plane:
          normal.SetCoord(0, 0, 1);
          u = x;
          v = y;
          break;
        case Kind::Cylinder:
          normal.SetCoord(x, y, 0);
          u = std::atan2(y, x);
          v = z;
          break;
        case Kind::Sphere:
          if (radial <= tolerance) return false;  // a pole
          normal.SetCoord(x, y, z);
          u = std::atan2(y, x);
          v = std::atan2(z, radial);
          break;
        case Kind::Cone: {
          const double r = radius + z * tanAngle;
          if (std::abs(r) <= tolerance) return false;  // the apex
          normal.SetCoord(x, y, -r * tanAngle);
          // On the far nappe the radius is negative: the point is at u + pi.
          u = r > 0 ? std::atan2(y, x) : std::atan2(-y, -x);
          v = z / cosAngle;
          break;
        }
        case Kind::Torus: {
          if (radial <= tolerance) return false;
          const double sum = x * x + y * y + z * z + radius * radius - minorRadius * minorRadius;
          normal.SetCoord(sum * x - 2 * radius * radius * x, sum * y - 2 * radius * radius * y, sum * z);
          // A spindle torus (minor radius above the major) also passes its axis: its inner
          // part has a negative radial coordinate, and the point is at u + pi there.
          const double outer = radial - radius, inner = -radial - radius, r2 = minorRadius * minorRadius;
          if (std::abs(outer * outer + z * z - r2) <= std::abs(inner * inner + z * z - r2)) {
            u = std::atan2(y, x);
            v = std::atan2(z, outer);
          } else {
            u = std::atan2(-y, -x);
            v = std::atan2(z, inner);
          }
          break;
        }
        case Kind::None:
          return false;
      }
      return true;
    }
  };
  std::vector<AnalyticSurface> analytic;
  // crossings(): the proxy triangles' boxes grown by their face's crossing band, in one tree
  // for the faces solved by Newton iteration and one tree per analytic face.
  BoxTree newtonFaceTree;
  std::vector<BoxTree> analyticFaceTree;
  std::vector<int> analyticFaces;

  // Exact crossings. An IntCurvesFace_Intersector keeps its results in itself, so like the
  // classifiers each query leases a set (one per face, built on first use) from a pool.
  std::vector<int> solidOfFace;                   // index into `solids`
  std::vector<Handle(Geom_Surface)> faceSurface;  // located, for normals at the hits
  struct FaceIntersectors {
    std::vector<std::unique_ptr<IntCurvesFace_Intersector>> byFace;
    // The parametric domain test IntCurvesFace_Intersector applies to its own solutions
    // (same class, same tolerance), for the Newton solutions.
    std::vector<std::unique_ptr<BRepTopAdaptor_FClass2d>> domainByFace;
    // projectOnPatch(): each face's surface with what its projections learnt of it.
    std::vector<Handle(ShapeAnalysis_Surface)> projectorByFace;
  };
  BRepTopAdaptor_FClass2d& domainOf(FaceIntersectors& lease, int face) const {
    auto& domain = lease.domainByFace[face];
    if (!domain) domain = std::make_unique<BRepTopAdaptor_FClass2d>(faces[face], classifyTolerance);
    return *domain;
  }
  mutable std::mutex intersectorMutex;
  mutable std::vector<std::unique_ptr<FaceIntersectors>> idleIntersectors;
  // A set of intersectors and domain tests for one query (made when none is idle), given back
  // after it.
  std::unique_ptr<FaceIntersectors> leaseIntersectors() const;
  void giveBack(std::unique_ptr<FaceIntersectors> lease) const;

  void index();
  bool proxyTrusted(const KPoint& q) const;
  Kernel::Triangle_3 proxyTriangle(ProxyMesh::Face_index f) const;
  void buildProxy(bool tessellate);  // false: the triangles the faces carry
  void measureCrossingBands();
  void findAnalyticSurfaces();
  void measureChordReach();
  // Whether parameters (u, v) of a point p of `face` lie in the face's domain, from the
  // face's parametric triangles holding p's neighbourhood: Unsure within the reach of a
  // boundary chord; else In when a triangle holds (u, v) (which is then moved into that
  // triangle's period), else Out.
  enum class Domain { In, Out, Unsure };
  Domain domainByTriangles(const gp_Pnt& p, int face, double& u, double& v, const size_t* triangles,
                           size_t count) const;
  bool classifyExact(const Point3& p) const;  // the next one where it is sure, else the last
  std::optional<bool> sideOfNearestAnalyticFace(const Point3& p) const;
  bool classifyByOpenCascade(const Point3& p) const;
  BoundaryProjection projectOnFace(const gp_Pnt& p, int face) const;
  // The nearest point to p of an analytic face's whole surface (closed form), with its
  // parameters, its distance and the distance of the next extremum (infinity if none);
  // nothing on other faces or where the extrema are not defined (p on an axis, at a centre).
  struct SurfaceFoot {
    gp_Pnt point;
    double u = 0, v = 0;
    double distance = 0, nextDistance = 0;
  };
  std::optional<SurfaceFoot> analyticFoot(const gp_Pnt& p, int face) const;
  bool surfaceFartherThan(const gp_Pnt& p, int face, double distance) const;
  // A face the segment may cross, and the part [t0, t1] of the segment where it may.
  // A proxy triangle near the segment and where the segment's line meets its plane
  // (segment parameter, barycentric weights).
  struct NewtonSeed {
    size_t triangle;
    double t;
    std::array<double, 3> weight;
    bool crossed;  // the segment crosses the triangle itself
  };
  struct FaceSpan {
    int face;
    double t0, t1;
    // False when some triangle near the segment is not a clean Newton start (too oblique, no
    // parameters, a pole or fold): then only OpenCASCADE's intersector on [t0, t1] gives the
    // answer for this face.
    bool newtonOnly = true;
    std::vector<NewtonSeed> seeds;
    // Every proxy triangle of the face whose box, grown by the face's crossing band, meets
    // the segment: the parametric triangle holding any crossing of the face is among them,
    // and so is every boundary chord within the band of a crossing.
    std::vector<size_t> near;
  };
  // Closed-form crossings of the segment with an analytic face: false when unsure (a grazing
  // or an end crossing, the line on the surface, a crossing near the face's boundary), the
  // face is then left to OpenCASCADE; else `found` holds the crossings (w along the line, u, v).
  struct LineHit {
    double w, u, v;
  };
  struct FaceIntersectors;
  bool analyticCrossings(const Point3& a, const Point3& d, double length, int face, std::vector<LineHit>& found,
                         std::vector<size_t>& near, FaceIntersectors& lease) const;
  // The crossing of the segment with the surface over a seed's triangle, by Newton
  // iteration on S(u,v) = a + t (b - a). Unsure: no convergence, near-tangent, near an end
  // of the segment, or a solution off the triangle. None: the crossing is beyond an end.
  // Crossing: on the seed's triangle. OffTriangle: a crossing of the line (t, uv set) over
  // some other parametric triangle.
  enum class NewtonResult { Crossing, None, OffTriangle, Unsure };
  // A line along `direction` steeper than 90 degrees minus the triangle's tilt (and a 10
  // degree margin): it crosses the surface patch over the triangle at most once and cannot
  // turn tangent to it there.
  bool steep(const NewtonTriangle& triangle, const gp_XYZ& direction) const {
    if (!triangle.regular) return false;
    const gp_XYZ p0 = triangle.node[0].XYZ();
    const gp_XYZ normal = (triangle.node[1].XYZ() - p0).Crossed(triangle.node[2].XYZ() - p0);
    const double steepness = std::abs(direction.Dot(normal)) / (direction.Modulus() * normal.Modulus());
    return std::acos(std::min(1.0, steepness)) + triangle.tilt < (80.0 / 180.0) * M_PI;
  }
  NewtonResult newtonCrossing(const Point3& a, const Point3& d, double length, int face, const NewtonSeed& seed,
                              double& t, gp_Pnt2d& uv) const;
  std::vector<FaceSpan> facesNearSegment(const Point3& a, const Point3& b) const;
  std::vector<BoundaryCrossing> exactCrossings(const Point3& a, const Point3& b,
                                               const std::vector<FaceSpan>& candidates) const;
};

}  // namespace oraclemesh
