// CGAL comes before any OpenCASCADE header: OCCT defines a function-like macro `Handle`
// that breaks CGAL's templates (CGAL/Lazy.h) when they are parsed after it.
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include "domain/BrepSolid.h"

#include <BRepAdaptor_Curve.hxx>
#include <Geom2d_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepGProp.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <IntAna_IntLinTorus.hxx>
#include <IntCurvesFace_Intersector.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <ShapeFix_Solid.hxx>
#include <gp_Lin.hxx>
#include <gp_Torus.hxx>
#include <gp_Ax3.hxx>
#include <gp_Pnt2d.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <unordered_map>

#include "Error.h"

namespace oraclemesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using KPoint = Kernel::Point_3;
using ProxyMesh = CGAL::Surface_mesh<KPoint>;
using ProxyPrimitive = CGAL::AABB_face_graph_triangle_primitive<ProxyMesh>;
using ProxyTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, ProxyPrimitive>>;
using ProxySide = CGAL::Side_of_triangle_mesh<ProxyMesh, Kernel>;

Point3 toPoint3(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }
gp_Pnt toGp(const Point3& p) { return gp_Pnt(p[0], p[1], p[2]); }

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || path.find_first_of("/\\", dot) != std::string::npos) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::string plural(int64_t n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

Bbox boxOf(const TopoDS_Shape& shape) {
  Bnd_Box box;
  // useTriangulation=false: the box of the exact geometry, not of an old tessellation.
  BRepBndLib::Add(shape, box, false);
  Bbox b;
  if (box.IsVoid()) return b;
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  b.add(Point3{x0, y0, z0});
  b.add(Point3{x1, y1, z1});
  return b;
}

// Edges bounding a single face of `shape`: holes in the surface. Degenerated edges (cone
// apex, sphere pole) and seams (the same face on both sides) are not holes.
int64_t countFreeEdges(const TopoDS_Shape& shape) {
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  int64_t freeEdges = 0;
  for (int i = 1; i <= edgeFaces.Extent(); ++i) {
    const TopoDS_Edge& e = TopoDS::Edge(edgeFaces.FindKey(i));
    if (BRep_Tool::Degenerated(e)) continue;
    const TopTools_ListOfShape& faces = edgeFaces.FindFromIndex(i);
    TopTools_IndexedMapOfShape distinct;
    for (const TopoDS_Shape& f : faces) distinct.Add(f);
    if (distinct.Extent() != 1) continue;
    if (BRep_Tool::IsClosed(e, TopoDS::Face(distinct(1)))) continue;
    ++freeEdges;
  }
  return freeEdges;
}

// Sews the faces of `shape` with a tolerance relative to the model size: shells that are
// closed up to tiny gaps (typical of STEP export) become closed.
TopoDS_Shape sewFaces(const TopoDS_Shape& shape, double tolerance) {
  BRepBuilderAPI_Sewing sewing(tolerance);
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) sewing.Add(ex.Current());
  sewing.Perform();
  return sewing.SewedShape();
}

TopoDS_Solid solidFromClosedShell(const TopoDS_Shell& shell) {
  // SolidFromShell builds the solid and orients its shell so that the volume is positive
  // (outward face normals), which BRepBuilderAPI_MakeSolid alone does not guarantee.
  ShapeFix_Solid fix;
  return fix.SolidFromShell(shell);
}

double signedVolume(const TopoDS_Shape& solid) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props);
  return props.Mass();
}

// The solids of one input in file order, and the open shells left out of it.
struct SolidPieces {
  std::vector<TopoDS_Solid> solids;
  std::vector<std::string> skipped;  // what was left out: "open shell (item 17 of 18, 3 faces, ...)"
};

// Walks compounds depth first so that solids and shells come out in the order the file (or
// FreeCAD's compound) lists them: that order is the priority of per-solid inputs.
void collectPieces(const TopoDS_Shape& shape, std::vector<TopoDS_Shape>& items, TopoDS_Compound& looseFaces,
                   int64_t& looseFaceCount) {
  switch (shape.ShapeType()) {
    case TopAbs_COMPOUND:
    case TopAbs_COMPSOLID:
      for (TopoDS_Iterator it(shape); it.More(); it.Next())
        collectPieces(it.Value(), items, looseFaces, looseFaceCount);
      break;
    case TopAbs_SOLID:
    case TopAbs_SHELL:
      items.push_back(shape);
      break;
    case TopAbs_FACE: {
      BRep_Builder builder;
      builder.Add(looseFaces, shape);
      ++looseFaceCount;
      break;
    }
    default:
      break;  // wires, edges and vertices bound no volume; counted only if nothing else is found
  }
}

std::string near(const TopoDS_Shape& shape) {
  const Bbox b = boxOf(shape);
  std::ostringstream out;
  out.precision(6);
  out << "(" << 0.5 * (b.min[0] + b.max[0]) << ", " << 0.5 * (b.min[1] + b.max[1]) << ", "
      << 0.5 * (b.min[2] + b.max[2]) << ")";
  return out.str();
}

int64_t countFaces(const TopoDS_Shape& shape) {
  int64_t n = 0;
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) ++n;
  return n;
}

// Turns whatever the user gave into solids, or explains why not. Policy for open shells
// (surfaces that bound no volume): beside at least one solid they are left out with a warning
// naming them (assemblies from CAD tools carry stray sheets, e.g. presse_asm.step); when
// nothing solid remains the input is an error. A solid whose own boundary is open is always
// an error: the user meant it to be a volume, and leaving it out would change the model.
SolidPieces solidPieces(const TopoDS_Shape& input, const std::string& what) {
  if (input.IsNull())
    throw InputError(what + " holds no geometry: select a solid, or a closed shell");
  const double sewTolerance = std::max(1e-6 * boxOf(input).diagonal(), 1e-7);

  std::vector<TopoDS_Shape> items;
  BRep_Builder builder;
  TopoDS_Compound faceBag;
  builder.MakeCompound(faceBag);
  int64_t looseFaces = 0;
  collectPieces(input, items, faceBag, looseFaces);

  SolidPieces pieces;
  struct OpenShell {
    size_t item;
    int64_t faces, freeEdges;
    std::string near;
  };
  std::vector<OpenShell> open;
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i].ShapeType() == TopAbs_SOLID) {
      const TopoDS_Solid& solid = TopoDS::Solid(items[i]);
      const int64_t freeEdges = countFreeEdges(solid);
      if (freeEdges > 0)
        throw InputError(what + " has a solid whose boundary is open (" + plural(freeEdges, "free edge") +
                         (items.size() > 1 ? ", item " + std::to_string(i + 1) + " of " + std::to_string(items.size()) +
                                                 " near " + near(solid)
                                           : "") +
                         "): repair the solid (Part > Check geometry, Part > Refine shape) or rebuild it from a "
                         "closed shell");
      pieces.solids.push_back(solid);
      continue;
    }
    TopoDS_Shape closed = items[i];
    if (countFreeEdges(items[i]) > 0) {
      // A shell that only lacks sewing (faces not sharing their edges) is still a closed
      // surface to the user; sewing is what FreeCAD's Shape builder would do.
      closed = sewFaces(items[i], sewTolerance);
      const int64_t sewnFree = countFreeEdges(closed);
      if (sewnFree > 0) {
        open.push_back({i, countFaces(items[i]), sewnFree, near(items[i])});
        continue;
      }
    }
    for (TopExp_Explorer ex(closed, TopAbs_SHELL); ex.More(); ex.Next())
      pieces.solids.push_back(solidFromClosedShell(TopoDS::Shell(ex.Current())));
  }

  // Loose faces (IGES files of trimmed surfaces, exploded shells) are sewn together first.
  bool looseFacesClose = true;
  int looseShells = 0;
  int64_t looseFree = 0;
  if (looseFaces > 0) {
    const TopoDS_Shape sewn = sewFaces(faceBag, sewTolerance);
    looseFree = countFreeEdges(sewn);
    for (TopExp_Explorer ex(sewn, TopAbs_SHELL); ex.More(); ex.Next()) ++looseShells;
    looseFacesClose = looseShells > 0 && looseFree == 0;
    if (looseFacesClose)
      for (TopExp_Explorer ex(sewn, TopAbs_SHELL); ex.More(); ex.Next())
        pieces.solids.push_back(solidFromClosedShell(TopoDS::Shell(ex.Current())));
  }

  if (pieces.solids.empty()) {
    if (open.size() == 1 && items.size() == 1 && looseFaces == 0)
      throw InputError(what + " is an open shell with " + plural(open.front().freeEdges, "free edge") +
                       ": close the surface or sew it (Part > Shape builder)");
    if (!open.empty()) {
      int64_t freeEdges = 0;
      for (const OpenShell& s : open) freeEdges += s.freeEdges;
      throw InputError(what + " holds only open shells (" + std::to_string(open.size()) + " shells with " +
                       plural(freeEdges, "free edge") + " in all) and no solid: close the surfaces or sew them "
                       "(Part > Shape builder)");
    }
    if (looseFaces > 0)
      throw InputError(what + " holds no solid (found " + plural(looseFaces, "face") +
                       (looseShells > 0 ? " that leave " + plural(looseFree, "free edge") + " when sewn" : "") +
                       "): select a solid, or a closed shell");
    int64_t edges = 0, vertices = 0;
    for (TopExp_Explorer ex(input, TopAbs_EDGE); ex.More(); ex.Next()) ++edges;
    for (TopExp_Explorer ex(input, TopAbs_VERTEX); ex.More(); ex.Next()) ++vertices;
    const std::string found = edges > 0 ? plural(edges, "edge") : vertices > 0 ? plural(vertices, "vertex") : "nothing";
    throw InputError(what + " holds no solid (found " + found + "): select a solid, or a closed shell");
  }

  for (const OpenShell& s : open)
    pieces.skipped.push_back("open shell (item " + std::to_string(s.item + 1) + " of " + std::to_string(items.size()) +
                             ", " + plural(s.faces, "face") + ", " + plural(s.freeEdges, "free edge") + ", near " +
                             s.near + ")");
  if (!looseFacesClose)
    pieces.skipped.push_back(plural(looseFaces, "loose face") + " that leave " + plural(looseFree, "free edge") +
                             " when sewn");

  for (TopoDS_Solid& solid : pieces.solids) {
    const double v = signedVolume(solid);
    if (v < 0) solid.Reverse();  // inside out (faces oriented inward): flip it
    if (!(std::abs(v) > 0))
      throw InputError(what + " has a solid with zero volume: select a solid that encloses a volume");
  }
  return pieces;
}

TopoDS_Shape compoundOf(const std::vector<TopoDS_Solid>& solids) {
  if (solids.size() == 1) return solids.front();
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  for (const TopoDS_Solid& s : solids) builder.Add(compound, s);
  return compound;
}

// The constructor's check: every part of the shape must be a volume. Loaders that may leave
// open shells out (with a warning) split the shape first and pass only its solids.
TopoDS_Shape validatedSolids(const TopoDS_Shape& input, const std::string& what) {
  const SolidPieces pieces = solidPieces(input, what);
  if (!pieces.skipped.empty())
    throw InputError(what + " holds, besides its solids, pieces that bound no volume (first: " + pieces.skipped.front() +
                     "): close them (Part > Shape builder), or leave them out of the input");
  return compoundOf(pieces.solids);
}

std::string describe(const std::string& name, const std::string& path) {
  return "input '" + name + "'" + (path.empty() ? "" : " (file '" + path + "')");
}

}  // namespace

// ------------------------------------------------------------------------------------------

namespace {

// Whether the segment a + t d, t in [0, 1], meets a box grown by a margin on every side (a
// slab test). Growing the box by the margin contains the ball of that radius around it, so
// this never rejects a box within the margin of the segment. The reciprocal direction is
// computed once per segment: the test runs for every AABB node the segment passes.
class SegmentBoxTest {
 public:
  SegmentBoxTest(const Point3& a, const Point3& d) : a_(a) {
    for (int i = 0; i < 3; ++i) inverse_[i] = d[i] != 0.0 ? 1.0 / d[i] : 0.0;
    for (int i = 0; i < 3; ++i) parallel_[i] = d[i] == 0.0;
  }
  bool meets(const CGAL::Bbox_3& box, double margin) const {
    double t0, t1;
    return meets(box, margin, t0, t1);
  }
  // Also gives the part [t0, t1] of the segment inside the grown box.
  bool meets(const CGAL::Bbox_3& box, double margin, double& t0, double& t1) const {
    t0 = 0.0;
    t1 = 1.0;
    for (int i = 0; i < 3; ++i) {
      const double lo = box.min(i) - margin, hi = box.max(i) + margin;
      if (parallel_[i]) {
        if (a_[i] < lo || a_[i] > hi) return false;
        continue;
      }
      double ta = (lo - a_[i]) * inverse_[i], tb = (hi - a_[i]) * inverse_[i];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (t0 > t1) return false;
    }
    return true;
  }

 private:
  Point3 a_, inverse_;
  bool parallel_[3];
};


// A bounding volume hierarchy over boxes (proxy triangles' boxes grown by their face's
// crossing band): which boxes a segment passes through, which boxes hold a point. Built once,
// then only read, so queries may run in parallel.
class BoxTree {
 public:
  void build(std::vector<CGAL::Bbox_3> boxes, std::vector<int> items) {
    boxes_ = std::move(boxes);
    items_ = std::move(items);
    nodes_.clear();
    if (items_.empty()) return;
    nodes_.emplace_back();
    split(0, 0, static_cast<int>(items_.size()));
  }
  bool empty() const { return nodes_.empty(); }
  const CGAL::Bbox_3& box() const { return nodes_.front().box; }
  // visit(item, t0, t1) for every box the segment meets, [t0, t1] its part of the segment.
  template <class Visit>
  void onSegment(const SegmentBoxTest& segment, Visit&& visit) const {
    double t0, t1;
    descend([&](const CGAL::Bbox_3& box) { return segment.meets(box, 0.0, t0, t1); },
            [&](int i) {
              if (segment.meets(boxes_[i], 0.0, t0, t1)) visit(items_[i], t0, t1);
            });
  }
  // visit(item) for every box holding p.
  template <class Visit>
  void atPoint(const gp_XYZ& p, Visit&& visit) const {
    descend([&](const CGAL::Bbox_3& box) { return holds(box, p); },
            [&](int i) {
              if (holds(boxes_[i], p)) visit(items_[i]);
            });
  }

 private:
  // Depth first through the nodes whose box `enters` accepts; atLeaf(i) for every box index
  // of the leaves reached (the caller tests the item's own box).
  template <class Enters, class AtLeaf>
  void descend(Enters&& enters, AtLeaf&& atLeaf) const {
    if (nodes_.empty()) return;
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!enters(node.box)) continue;
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) atLeaf(i);
      } else {
        stack[top++] = node.first;
        stack[top++] = node.first + 1;
      }
    }
  }

  struct Node {
    CGAL::Bbox_3 box;
    int first = 0;  // leaf: first box; inner node: index of the first of its two children
    int count = 0;  // boxes of a leaf, 0 for an inner node
  };
  static bool holds(const CGAL::Bbox_3& b, const gp_XYZ& p) {
    return p.X() >= b.xmin() && p.X() <= b.xmax() && p.Y() >= b.ymin() && p.Y() <= b.ymax() && p.Z() >= b.zmin() &&
           p.Z() <= b.zmax();
  }
  // Makes node `index` the root of boxes [begin, end): halves them at the median of the box
  // centres along the widest axis (depth ~ log2 n, far below the stack size). The two
  // children of a node are stored next to each other, so a node needs only the first index.
  void split(int index, int begin, int end) {
    CGAL::Bbox_3 box = boxes_[begin];
    for (int i = begin + 1; i < end; ++i) box += boxes_[i];
    nodes_[index].box = box;
    if (end - begin <= 4) {
      nodes_[index].first = begin;
      nodes_[index].count = end - begin;
      return;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (box.max(k) - box.min(k) > box.max(axis) - box.min(axis)) axis = k;
    std::vector<int> order(end - begin);
    for (int i = begin; i < end; ++i) order[i - begin] = i;
    const int middle = (end - begin) / 2;
    std::nth_element(order.begin(), order.begin() + middle, order.end(), [&](int x, int y) {
      return boxes_[x].min(axis) + boxes_[x].max(axis) < boxes_[y].min(axis) + boxes_[y].max(axis);
    });
    std::vector<CGAL::Bbox_3> sortedBoxes;
    std::vector<int> sortedItems;
    for (int i : order) {
      sortedBoxes.push_back(boxes_[i]);
      sortedItems.push_back(items_[i]);
    }
    std::copy(sortedBoxes.begin(), sortedBoxes.end(), boxes_.begin() + begin);
    std::copy(sortedItems.begin(), sortedItems.end(), items_.begin() + begin);
    const int children = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[index].first = children;
    nodes_[index].count = 0;
    split(children, begin, begin + middle);
    split(children + 1, begin + middle, end);
  }
  std::vector<CGAL::Bbox_3> boxes_;
  std::vector<int> items_;
  std::vector<Node> nodes_;
};

}  // namespace

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
    double tanAngle = 0, cosAngle = 1;  // cone half-angle
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
  };
  BRepTopAdaptor_FClass2d& domainOf(FaceIntersectors& lease, int face) const {
    auto& domain = lease.domainByFace[face];
    if (!domain) domain = std::make_unique<BRepTopAdaptor_FClass2d>(faces[face], classifyTolerance);
    return *domain;
  }
  mutable std::mutex intersectorMutex;
  mutable std::vector<std::unique_ptr<FaceIntersectors>> idleIntersectors;

  void index();
  bool proxyTrusted(const KPoint& q) const;
  Kernel::Triangle_3 proxyTriangle(ProxyMesh::Face_index f) const;
  void buildProxy();
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
  bool classifyExact(const Point3& p) const;
  BoundaryProjection projectOnFace(const gp_Pnt& p, int face) const;
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

void BrepSolid::Impl::index() {
  TopExp::MapShapes(shape, TopAbs_FACE, faceMap);
  TopExp::MapShapes(shape, TopAbs_EDGE, edgeMap);
  for (int i = 1; i <= faceMap.Extent(); ++i) faces.push_back(TopoDS::Face(faceMap(i)));
  for (int i = 1; i <= edgeMap.Extent(); ++i) edges.push_back(TopoDS::Edge(edgeMap(i)));
  edgeFaces.assign(edges.size(), {});
  for (size_t f = 0; f < faces.size(); ++f)
    for (TopExp_Explorer ex(faces[f], TopAbs_EDGE); ex.More(); ex.Next()) {
      const int e = edgeMap.FindIndex(ex.Current()) - 1;
      std::vector<int>& list = edgeFaces[e];
      if (std::find(list.begin(), list.end(), static_cast<int>(f)) == list.end()) list.push_back(static_cast<int>(f));
    }
  for (TopExp_Explorer ex(shape, TopAbs_VERTEX); ex.More(); ex.Next())
    maxShapeTolerance = std::max(maxShapeTolerance, BRep_Tool::Tolerance(TopoDS::Vertex(ex.Current())));
  for (const TopoDS_Edge& e : edges) maxShapeTolerance = std::max(maxShapeTolerance, BRep_Tool::Tolerance(e));
  for (const TopoDS_Face& f : faces) maxShapeTolerance = std::max(maxShapeTolerance, BRep_Tool::Tolerance(f));

  for (TopExp_Explorer ex(shape, TopAbs_SOLID); ex.More(); ex.Next()) {
    auto pool = std::make_unique<ClassifierPool>();
    pool->solid = ex.Current();
    pool->box = boxOf(ex.Current());
    solids.push_back(std::move(pool));
  }
  solidOfFace.assign(faces.size(), 0);
  for (size_t s = 0; s < solids.size(); ++s)
    for (TopExp_Explorer ex(solids[s]->solid, TopAbs_FACE); ex.More(); ex.Next())
      solidOfFace[faceMap.FindIndex(ex.Current()) - 1] = static_cast<int>(s);
  for (const TopoDS_Face& f : faces) faceSurface.push_back(BRep_Tool::Surface(f));
}

void BrepSolid::Impl::buildProxy() {
  // A deflection relative to the model size keeps the proxy's triangle count independent of
  // the units; the exact band below follows whatever BRepMesh actually achieved.
  // 2e-4 keeps curved faces' exact bands thin (most Mesh_3 queries are near the surface)
  // at a few thousand triangles for typical parts.
  const double requested = 2e-4 * diagonal;
  BRepMesh_IncrementalMesh mesher(shape, requested, Standard_False, 0.5, Standard_False);
  (void)mesher;

  bool complete = true;
  // Starts at zero: a planar face's triangles lie on it, and its band then shrinks to the
  // model tolerance (the polygon-versus-curve gaps at its curved edges lie within the band of
  // the curved neighbour face).
  std::vector<double> measuredOfFace(faces.size(), 0.0);
  proxyFaceOfTriangle.clear();
  std::map<std::array<double, 3>, int> nodeIds;  // exact-coordinate identity, for the gap count
  std::map<std::pair<int, int>, int> edgeUse;
  for (size_t f = 0; f < faces.size(); ++f) {
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull() || tri->NbTriangles() == 0) {
      complete = false;
      facesWithoutTriangles.push_back(static_cast<int>(f));
      continue;
    }
    double& measured = measuredOfFace[f];
    measured = std::max(measured, tri->Deflection());
    const gp_Trsf trsf = loc.Transformation();
    const bool reversed = faces[f].Orientation() == TopAbs_REVERSED;
    std::vector<ProxyMesh::Vertex_index> local(tri->NbNodes() + 1);
    std::vector<gp_Pnt> nodes(tri->NbNodes() + 1);
    std::vector<int> ids(tri->NbNodes() + 1);
    for (int n = 1; n <= tri->NbNodes(); ++n) {
      nodes[n] = tri->Node(n).Transformed(trsf);
      local[n] = proxyMesh.add_vertex(KPoint(nodes[n].X(), nodes[n].Y(), nodes[n].Z()));
      auto it = nodeIds.emplace(std::array<double, 3>{nodes[n].X(), nodes[n].Y(), nodes[n].Z()},
                                static_cast<int>(nodeIds.size())).first;
      ids[n] = it->second;
    }
    // Measure the real deviation: the surface at a triangle's parametric centroid and edge
    // midpoints against the flat triangle there. BRepMesh's own figure is an estimate.
    BRepAdaptor_Surface surface(faces[f], Standard_True);
    const Handle(Geom_Surface) exactSurface = BRep_Tool::Surface(faces[f]);
    // Nodes on an edge of the triangulation that is not shared by exactly two triangles.
    std::vector<char> boundaryNode(tri->NbNodes() + 1, 0);
    {
      std::map<std::pair<int, int>, int> use;
      for (int t = 1; t <= tri->NbTriangles(); ++t) {
        int a, b, c;
        tri->Triangle(t).Get(a, b, c);
        for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) ++use[{std::min(u, v), std::max(u, v)}];
      }
      for (const auto& [e, n] : use)
        if (n != 2) boundaryNode[e.first] = boundaryNode[e.second] = 1;
    }
    const size_t firstTriangle = newtonTriangle.size();
    std::vector<std::array<int, 3>> keptCorners;  // triangulation nodes of the kept triangles
    for (int t = 1; t <= tri->NbTriangles(); ++t) {
      int a, b, c;
      tri->Triangle(t).Get(a, b, c);
      if (reversed) std::swap(b, c);
      if (ids[a] == ids[b] || ids[b] == ids[c] || ids[a] == ids[c]) continue;  // collapsed at a pole
      const gp_Vec ab(nodes[a], nodes[b]), ac(nodes[a], nodes[c]);
      if (ab.Crossed(ac).Magnitude() <= 1e-30 * diagonal * diagonal) continue;
      // Each triangle gets its own corner vertices: Side_of_triangle_mesh only needs the
      // triangles, and a soup never fails on non-manifold joins between faces.
      proxyMesh.add_face(local[a], local[b], local[c]);
      proxyFaceOfTriangle.push_back(static_cast<int>(f));
      NewtonTriangle& seedTriangle = newtonTriangle.emplace_back();
      seedTriangle.node = {nodes[a], nodes[b], nodes[c]};
      keptCorners.push_back({a, b, c});
      seedTriangle.corner = {a, b, c};
      for (auto [u, v] : {std::pair{ids[a], ids[b]}, std::pair{ids[b], ids[c]}, std::pair{ids[c], ids[a]}})
        ++edgeUse[{std::min(u, v), std::max(u, v)}];
      if (tri->HasUVNodes()) {
        const gp_Pnt2d ua = tri->UVNode(a), ub = tri->UVNode(b), uc = tri->UVNode(c);
        seedTriangle.uv = {ua, ub, uc};
        seedTriangle.regular = true;
        seedTriangle.interior = !boundaryNode[a] && !boundaryNode[b] && !boundaryNode[c];
        const gp_Dir triangleNormal(ab.Crossed(ac));
        // Normals at the corners, the centroid and the edge midpoints (the tilt's samples).
        const std::array<std::array<double, 3>, 7> tiltWeights{
            {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1 / 3., 1 / 3., 1 / 3.}, {.5, .5, 0}, {0, .5, .5}, {.5, 0, .5}}};
        int sense = 0;
        for (const auto& w : tiltWeights) {
          gp_Pnt p;
          gp_Vec du, dv;
          surface.D1(w[0] * ua.X() + w[1] * ub.X() + w[2] * uc.X(), w[0] * ua.Y() + w[1] * ub.Y() + w[2] * uc.Y(), p,
                     du, dv);
          const gp_Vec n = du.Crossed(dv);
          if (n.Magnitude() <= 1e-12 * du.Magnitude() * dv.Magnitude() || n.Magnitude() == 0) {
            seedTriangle.regular = false;  // a singular point: leave it to OpenCASCADE
            break;
          }
          // The triangle's winding may disagree with the parametrisation's, so the first
          // sample sets the sense; a normal turning over within the triangle (a fold) rules
          // the triangle out.
          const double cosine = triangleNormal.Dot(gp_Dir(n));
          if (sense == 0) sense = cosine < 0 ? -1 : 1;
          if (cosine * sense <= 0) {
            seedTriangle.regular = false;
            break;
          }
          seedTriangle.tilt = std::max(seedTriangle.tilt, std::acos(std::min(1.0, cosine * sense)));
        }
        const std::array<std::array<double, 3>, 4> weights{{{1 / 3., 1 / 3., 1 / 3.}, {.5, .5, 0}, {0, .5, .5}, {.5, 0, .5}}};
        for (const auto& w : weights) {
          const gp_Pnt onSurface = surface.Value(w[0] * ua.X() + w[1] * ub.X() + w[2] * uc.X(),
                                                 w[0] * ua.Y() + w[1] * ub.Y() + w[2] * uc.Y());
          const gp_Pnt onTriangle(w[0] * nodes[a].X() + w[1] * nodes[b].X() + w[2] * nodes[c].X(),
                                  w[0] * nodes[a].Y() + w[1] * nodes[b].Y() + w[2] * nodes[c].Y(),
                                  w[0] * nodes[a].Z() + w[1] * nodes[b].Z() + w[2] * nodes[c].Z());
          double deviation = onSurface.Distance(onTriangle);
          // The parametric correspondence only bounds the deviation from above; where the
          // bound is large (strongly non-uniform parametrisations) ask for the true distance,
          // so that a distorted parametrisation does not widen the exact band for nothing.
          if (deviation > requested) {
            GeomAPI_ProjectPointOnSurf projection(onTriangle, exactSurface);
            if (projection.IsDone() && projection.NbPoints() > 0)
              deviation = std::min(deviation, projection.LowerDistance());
          }
          measured = std::max(measured, deviation);
        }
      }
    }
    // Chords used by one kept triangle only (by triangulation node, so that a seam's two
    // sides stay apart).
    std::map<std::pair<int, int>, int> keptEdgeUse;
    for (const auto& corners : keptCorners)
      for (int k = 0; k < 3; ++k)
        ++keptEdgeUse[{std::min(corners[k], corners[(k + 1) % 3]), std::max(corners[k], corners[(k + 1) % 3])}];
    for (size_t i = 0; i < keptCorners.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const int p = keptCorners[i][k], q = keptCorners[i][(k + 1) % 3];
        newtonTriangle[firstTriangle + i].boundaryEdge[k] = keptEdgeUse[{std::min(p, q), std::max(p, q)}] == 1;
      }
  }
  // Ray parity only needs every tessellation edge to be used an even number of times (a
  // closed surface mod 2): BRepMesh sometimes folds a B-spline face onto itself, which uses
  // edges four times and is harmless.
  for (const auto& [edge, uses] : edgeUse)
    if (uses % 2 != 0) ++proxy.unpairedEdges;

  proxy.triangles = proxyFaceOfTriangle.size();
  // Margin for the deviation between sampled points, plus the model's own tolerance (a
  // STEP file's edges may sit that far from their faces).
  // A badly parametrised face deviates more than the rest; keeping its band to itself keeps
  // the exact (slow) queries near that face only.
  faceBand.resize(faces.size());
  patchDeviation.resize(faces.size());
  proxy.deflection = 0;
  for (size_t f = 0; f < faces.size(); ++f) {
    // The face's own tolerance (its edges' and vertices' included), not the model's largest:
    // one sloppy edge (U_Joint_2 has a few at 0.02 mm, most at 4e-4) then widens the
    // exact band near its faces only.
    double tolerance = BRep_Tool::Tolerance(faces[f]);
    for (TopExp_Explorer ex(faces[f], TopAbs_EDGE); ex.More(); ex.Next())
      tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Edge(ex.Current())));
    for (TopExp_Explorer ex(faces[f], TopAbs_VERTEX); ex.More(); ex.Next())
      tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Vertex(ex.Current())));
    const double h = 1.5 * measuredOfFace[f] + tolerance;
    patchDeviation[f] = h;
    proxy.deflection = std::max(proxy.deflection, h);
    faceBand[f] = 2 * h + 1e-9 * diagonal;
  }
  proxy.exactBand = 2 * proxy.deflection + 1e-9 * diagonal;
  // A face without triangles or gaps between faces (rays could slip through) make the
  // proxy unreliable: then every query is answered exactly.
  proxy.usable = complete && proxy.triangles > 0 && proxy.unpairedEdges == 0;
  if (proxy.triangles == 0) return;
  proxyTree = std::make_unique<ProxyTree>(proxyMesh.faces().begin(), proxyMesh.faces().end(), proxyMesh);
  proxyTree->build();
  proxyTree->accelerate_distance_queries();  // built now, so that const queries never build
  if (proxy.usable) proxySide = std::make_unique<ProxySide>(*proxyTree);
  for (ProxyMesh::Face_index f : proxyMesh.faces()) proxyTriangleBox.push_back(proxyTriangle(f).bbox());
  measureCrossingBands();
  measureChordReach();
  findAnalyticSurfaces();
}

void BrepSolid::Impl::measureChordReach() {
  std::vector<std::vector<size_t>> trianglesOfFace(faces.size());
  for (size_t id = 0; id < proxyFaceOfTriangle.size(); ++id) trianglesOfFace[proxyFaceOfTriangle[id]].push_back(id);
  period.assign(faces.size(), {0.0, 0.0});
  for (size_t f = 0; f < faces.size(); ++f) {
    const BRepAdaptor_Surface surface(faces[f], Standard_True);
    if (surface.IsUPeriodic()) period[f][0] = surface.UPeriod();
    if (surface.IsVPeriodic()) period[f][1] = surface.VPeriod();
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull() || !tri->HasUVNodes()) continue;
    // Parametric sagitta of each chord of each edge: the edge's parametric curve at the middle
    // parameter against the chord's middle; plus the edge's tolerance in parameter units.
    std::map<std::pair<int, int>, double> reachOfChord;
    for (TopExp_Explorer ex(faces[f], TopAbs_EDGE); ex.More(); ex.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(ex.Current());
      TopLoc_Location edgeLoc;
      const Handle(Poly_PolygonOnTriangulation) polygon = BRep_Tool::PolygonOnTriangulation(edge, tri, edgeLoc);
      if (polygon.IsNull() || polygon->Parameters().IsNull()) continue;
      double first, last;
      const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, faces[f], first, last);
      if (pcurve.IsNull()) continue;
      const double tolerance = 2 * BRep_Tool::Tolerance(edge) + classifyTolerance;
      const TColStd_Array1OfInteger& nodes = polygon->Nodes();
      const TColStd_Array1OfReal& parameters = polygon->Parameters()->Array1();
      for (int i = nodes.Lower(); i < nodes.Upper(); ++i) {
        const gp_Pnt2d p0 = tri->UVNode(nodes(i)), p1 = tri->UVNode(nodes(i + 1));
        const gp_Pnt2d middle((p0.XY() + p1.XY()) / 2);
        const gp_Pnt2d onCurve = pcurve->Value(0.5 * (parameters(i) + parameters(i + 1)));
        // A 3D tolerance in parameters: divided by the smaller speed of the parametrisation.
        gp_Pnt point;
        gp_Vec du, dv;
        surface.D1(middle.X(), middle.Y(), point, du, dv);
        const double speed = std::min(du.Magnitude(), dv.Magnitude());
        if (!(speed > 1e-9)) continue;  // degenerate here: leave the chord unmeasured
        // A seam's polygon and parametric curve may be those of its two sides: compare
        // them modulo the periods.
        gp_XY gap = onCurve.XY() - middle.XY();
        if (period[f][0] > 0) gap.SetX(gap.X() - period[f][0] * std::round(gap.X() / period[f][0]));
        if (period[f][1] > 0) gap.SetY(gap.Y() - period[f][1] * std::round(gap.Y() / period[f][1]));
        const double reach = 1.5 * gap.Modulus() + tolerance / speed;
        double& slot = reachOfChord[{std::min(nodes(i), nodes(i + 1)), std::max(nodes(i), nodes(i + 1))}];
        slot = std::max(slot, reach);
      }
    }
    for (size_t id : trianglesOfFace[f]) {
      NewtonTriangle& triangle = newtonTriangle[id];
      for (int k = 0; k < 3; ++k) {
        if (!triangle.boundaryEdge[k]) continue;
        const int p = triangle.corner[k], q = triangle.corner[(k + 1) % 3];
        const auto it = reachOfChord.find({std::min(p, q), std::max(p, q)});
        if (it != reachOfChord.end()) triangle.chordReach[k] = it->second;
      }
    }
  }
}

void BrepSolid::Impl::findAnalyticSurfaces() {
  analytic.assign(faces.size(), {});
  for (size_t f = 0; f < faces.size(); ++f) {
    // The closed form classifies its solutions by the face's parametric triangles.
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull() || !tri->HasUVNodes()) continue;
    const BRepAdaptor_Surface surface(faces[f], Standard_True);  // location applied
    AnalyticSurface& s = analytic[f];
    switch (surface.GetType()) {
      case GeomAbs_Plane:
        s.kind = AnalyticSurface::Kind::Plane;
        s.frame = surface.Plane().Position();
        break;
      case GeomAbs_Cylinder:
        s.kind = AnalyticSurface::Kind::Cylinder;
        s.frame = surface.Cylinder().Position();
        s.radius = surface.Cylinder().Radius();
        break;
      case GeomAbs_Cone:
        s.kind = AnalyticSurface::Kind::Cone;
        s.frame = surface.Cone().Position();
        s.radius = surface.Cone().RefRadius();
        s.tanAngle = std::tan(surface.Cone().SemiAngle());
        s.cosAngle = std::cos(surface.Cone().SemiAngle());
        break;
      case GeomAbs_Sphere:
        s.kind = AnalyticSurface::Kind::Sphere;
        s.frame = surface.Sphere().Position();
        s.radius = surface.Sphere().Radius();
        break;
      case GeomAbs_Torus:
        s.kind = AnalyticSurface::Kind::Torus;
        s.torus = surface.Torus();
        s.frame = s.torus.Position();
        s.radius = s.torus.MajorRadius();
        s.minorRadius = s.torus.MinorRadius();
        break;
      default:
        break;
    }
  }
  std::vector<std::vector<CGAL::Bbox_3>> boxesOfFace(faces.size());
  std::vector<std::vector<int>> trianglesOfFace(faces.size());
  std::vector<CGAL::Bbox_3> newtonBoxes;
  std::vector<int> newtonTriangles;
  for (size_t id = 0; id < proxyFaceOfTriangle.size(); ++id) {
    const int f = proxyFaceOfTriangle[id];
    const double m = crossingBand[f];
    const CGAL::Bbox_3& b = proxyTriangleBox[id];
    const CGAL::Bbox_3 grown(b.xmin() - m, b.ymin() - m, b.zmin() - m, b.xmax() + m, b.ymax() + m, b.zmax() + m);
    if (analytic[f].kind == AnalyticSurface::Kind::None) {
      newtonBoxes.push_back(grown);
      newtonTriangles.push_back(static_cast<int>(id));
    } else {
      boxesOfFace[f].push_back(grown);
      trianglesOfFace[f].push_back(static_cast<int>(id));
    }
  }
  analyticFaceTree.resize(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    if (analytic[f].kind == AnalyticSurface::Kind::None) continue;
    // The parameters the closed form gives must be the face's own (they are unless the
    // location scales or mirrors the surface): checked at the triangulation's nodes.
    const AnalyticSurface& s = analytic[f];
    bool agrees = !trianglesOfFace[f].empty();  // else no triangles to classify with
    for (int id : trianglesOfFace[f])
      for (const gp_Pnt& node : newtonTriangle[id].node) {
        const gp_XYZ local = node.XYZ() - s.frame.Location().XYZ();
        double u, v;
        gp_XYZ normal;
        if (!s.parameters(local.Dot(s.frame.XDirection().XYZ()), local.Dot(s.frame.YDirection().XYZ()),
                          local.Dot(s.frame.Direction().XYZ()), classifyTolerance, u, v, normal))
          continue;
        if (faceSurface[f]->Value(u, v).Distance(node) > 1e-6 * diagonal + 2 * maxShapeTolerance) agrees = false;
      }
    if (!agrees) {
      analytic[f].kind = AnalyticSurface::Kind::None;  // Newton iteration answers instead
      for (size_t i = 0; i < trianglesOfFace[f].size(); ++i) {
        newtonBoxes.push_back(boxesOfFace[f][i]);
        newtonTriangles.push_back(trianglesOfFace[f][i]);
      }
      continue;
    }
    analyticFaceTree[f].build(std::move(boxesOfFace[f]), std::move(trianglesOfFace[f]));
    analyticFaces.push_back(static_cast<int>(f));
  }
  newtonFaceTree.build(std::move(newtonBoxes), std::move(newtonTriangles));
}

void BrepSolid::Impl::measureCrossingBands() {
  crossingBand = faceBand;
  for (size_t f = 0; f < faces.size(); ++f) {
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull()) continue;
    const gp_Trsf trsf = loc.Transformation();
    double sagitta = 0;
    for (TopExp_Explorer ex(faces[f], TopAbs_EDGE); ex.More(); ex.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(ex.Current());
      if (BRep_Tool::Degenerated(edge)) continue;
      TopLoc_Location edgeLoc;
      const Handle(Poly_PolygonOnTriangulation) polygon = BRep_Tool::PolygonOnTriangulation(edge, tri, edgeLoc);
      if (polygon.IsNull() || polygon->Parameters().IsNull()) {
        sagitta = std::max(sagitta, proxy.deflection);  // unknown: assume the worst measured
        continue;
      }
      const BRepAdaptor_Curve curve(edge);
      const TColStd_Array1OfInteger& nodes = polygon->Nodes();
      const TColStd_Array1OfReal& parameters = polygon->Parameters()->Array1();
      for (int i = nodes.Lower(); i < nodes.Upper(); ++i) {
        const gp_Pnt p0 = tri->Node(nodes(i)).Transformed(trsf), p1 = tri->Node(nodes(i + 1)).Transformed(trsf);
        const gp_Pnt chordMiddle((p0.XYZ() + p1.XYZ()) / 2);
        const gp_Pnt onCurve = curve.Value(0.5 * (parameters(i) + parameters(i + 1)));
        sagitta = std::max(sagitta, chordMiddle.Distance(onCurve));
      }
    }
    // The midpoint sample bounds the sagitta of a circle-like arc up to sampling: 1.5 keeps
    // a margin as in the face bands.
    crossingBand[f] = faceBand[f] + 1.5 * sagitta;
  }
}

Kernel::Triangle_3 BrepSolid::Impl::proxyTriangle(ProxyMesh::Face_index f) const {
  const auto he = proxyMesh.halfedge(f);
  return Kernel::Triangle_3(proxyMesh.point(proxyMesh.source(he)), proxyMesh.point(proxyMesh.target(he)),
                            proxyMesh.point(proxyMesh.target(proxyMesh.next(he))));
}

// The proxy's side answer holds at q when q is outside every face's band: farther from that
// face's triangles than twice the face's deviation from the B-rep.
bool BrepSolid::Impl::proxyTrusted(const KPoint& q) const {
  // One traversal that stops at the first triangle within its face's band. Boxes are pruned
  // by a plain floating-point distance with a relative margin: CGAL's exact ball/box
  // predicate falls back to multi-precision arithmetic so often that it cost a third of
  // inside(), and a prefilter only needs to never prune a box it should keep.
  struct Traversal {
    const Impl& m;
    KPoint q;
    double reachSquared;
    bool trusted = true;

    double squaredDistanceToBox(const CGAL::Bbox_3& box) const {
      double sum = 0;
      for (int i = 0; i < 3; ++i) {
        const double c = q[i];
        const double gap = c < box.min(i) ? box.min(i) - c : (c > box.max(i) ? c - box.max(i) : 0.0);
        sum += gap * gap;
      }
      return sum;
    }
    bool go_further() const { return trusted; }
    void intersection(int, const ProxyPrimitive& primitive) {
      const size_t id = static_cast<size_t>(primitive.id());
      const double band = m.faceBand[m.proxyFaceOfTriangle[id]];
      if (squaredDistanceToBox(m.proxyTriangleBox[id]) > band * band * (1 + 1e-9)) return;
      if (CGAL::to_double(CGAL::squared_distance(q, m.proxyTriangle(primitive.id()))) <= band * band) trusted = false;
    }
    bool do_intersect(int, const CGAL::AABB_node<CGAL::AABB_traits<Kernel, ProxyPrimitive>>& node) const {
      return squaredDistanceToBox(node.bbox()) <= reachSquared;
    }
  };
  Traversal traversal{*this, q, proxy.exactBand * proxy.exactBand * (1 + 1e-9)};
  proxyTree->traversal(0, traversal);
  return traversal.trusted;
}

bool BrepSolid::Impl::classifyExact(const Point3& p) const {
  const gp_Pnt q = toGp(p);
  for (const auto& pool : solids) {
    if (!pool->box.contains(p, classifyTolerance)) continue;
    std::unique_ptr<BRepClass3d_SolidClassifier> classifier;
    {
      std::lock_guard<std::mutex> lock(pool->mutex);
      if (!pool->idle.empty()) {
        classifier = std::move(pool->idle.back());
        pool->idle.pop_back();
      }
    }
    if (!classifier) {
      classifier = std::make_unique<BRepClass3d_SolidClassifier>();
      classifier->Load(pool->solid);
    }
    classifier->Perform(q, classifyTolerance);
    const TopAbs_State state = classifier->State();
    {
      std::lock_guard<std::mutex> lock(pool->mutex);
      pool->idle.push_back(std::move(classifier));
    }
    if (state == TopAbs_IN || state == TopAbs_ON) return true;
  }
  return false;
}

BoundaryProjection BrepSolid::Impl::projectOnFace(const gp_Pnt& p, int face) const {
  BoundaryProjection best;
  // DistShapeShape handles the trimmed face completely: the surface extremum when its
  // (u,v) classifies inside the face, else the nearest point of the bounding edges.
  BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(p).Vertex(), faces[face], Extrema_ExtFlag_MIN);
  if (!dist.IsDone() || dist.NbSolution() == 0) return best;
  best.point = toPoint3(dist.PointOnShape2(1));
  best.distance = dist.Value();
  best.patch = face;
  return best;
}

BrepSolid::Impl::Domain BrepSolid::Impl::domainByTriangles(const gp_Pnt& p, int face, double& u, double& v,
                                                           const size_t* triangles, size_t count) const {
  const double uPeriod = period[face][0], vPeriod = period[face][1];
  const double band = crossingBand[face];
  bool inside = false;
  double insideU = u, insideV = v;
  for (size_t i = 0; i < count; ++i) {
    const NewtonTriangle& triangle = newtonTriangle[triangles[i]];
    const gp_XY p0 = triangle.uv[0].XY(), e1 = triangle.uv[1].XY() - p0, e2 = triangle.uv[2].XY() - p0;
    // (u, v) in the period of this triangle's parameters.
    double uu = u, vv = v;
    if (uPeriod > 0) uu += uPeriod * std::round((p0.X() + (e1.X() + e2.X()) / 3 - u) / uPeriod);
    if (vPeriod > 0) vv += vPeriod * std::round((p0.Y() + (e1.Y() + e2.Y()) / 3 - v) / vPeriod);
    const gp_XY q(uu, vv);
    for (int k = 0; k < 3; ++k) {
      if (!triangle.boundaryEdge[k]) continue;
      if (triangle.chordReach[k] < 0) {
        const gp_XYZ s0 = triangle.node[k].XYZ(), chord = triangle.node[(k + 1) % 3].XYZ() - s0;
        const double lengthSquared = chord.SquareModulus();
        const double along = lengthSquared > 0 ? std::clamp((p.XYZ() - s0).Dot(chord) / lengthSquared, 0.0, 1.0) : 0.0;
        if ((p.XYZ() - (s0 + along * chord)).SquareModulus() <= band * band) return Domain::Unsure;
        continue;
      }
      const gp_XY s0 = triangle.uv[k].XY(), chord = triangle.uv[(k + 1) % 3].XY() - s0;
      const double lengthSquared = chord.SquareModulus();
      const double along = lengthSquared > 0 ? std::clamp((q - s0).Dot(chord) / lengthSquared, 0.0, 1.0) : 0.0;
      if ((q - (s0 + along * chord)).SquareModulus() <= triangle.chordReach[k] * triangle.chordReach[k])
        return Domain::Unsure;
    }
    if (inside) continue;
    const double area = e1.Crossed(e2);
    if (area == 0) continue;
    const gp_XY r = q - p0;
    const double w1 = r.Crossed(e2) / area, w2 = e1.Crossed(r) / area;
    const double slack = -1e-9;  // a point on an edge shared by two triangles is in either
    if (w1 >= slack && w2 >= slack && 1 - w1 - w2 >= slack) {
      inside = true;
      insideU = uu;
      insideV = vv;
    }
  }
  if (!inside) return Domain::Out;
  u = insideU;
  v = insideV;
  return Domain::In;
}

bool BrepSolid::Impl::analyticCrossings(const Point3& a, const Point3& d, double length, int f,
                                        std::vector<LineHit>& found, std::vector<size_t>& near,
                                        FaceIntersectors& lease) const {
  const AnalyticSurface& s = analytic[f];
  using Kind = AnalyticSurface::Kind;
  const gp_XYZ X = s.frame.XDirection().XYZ(), Y = s.frame.YDirection().XYZ(), Z = s.frame.Direction().XYZ();
  const gp_XYZ dir = gp_XYZ(d[0], d[1], d[2]) / length;
  const gp_XYZ o = gp_XYZ(a[0], a[1], a[2]) - s.frame.Location().XYZ();
  // The line in the surface's frame: (ox, oy, oz) + w (dx, dy, dz), w the distance from a.
  const double ox = o.Dot(X), oy = o.Dot(Y), oz = o.Dot(Z);
  const double dx = dir.Dot(X), dy = dir.Dot(Y), dz = dir.Dot(Z);
  const double tolerance = classifyTolerance;
  std::array<double, 4> roots;
  int rootCount = 0;
  // Roots of A w^2 + B w + C (A != 0), without cancellation; none when the line misses (a
  // tangent line's double root is a touch, dropped like OpenCASCADE's tangent points).
  auto quadratic = [&](double A, double B, double C) {
    const double discriminant = B * B - 4 * A * C;
    if (discriminant < 0) return;
    const double q = -0.5 * (B + std::copysign(std::sqrt(discriminant), B));
    if (q != 0) {
      roots[rootCount++] = q / A;
      roots[rootCount++] = C / q;
    } else {
      roots[rootCount++] = 0;  // B = C = 0: a double root at a, an end crossing
    }
  };
  switch (s.kind) {
    case Kind::Plane:
      if (std::abs(dz) <= 1e-12) {
        if (std::abs(oz) <= tolerance) return false;  // the line lies in the plane
        break;
      }
      roots[rootCount++] = -oz / dz;
      break;
    case Kind::Cylinder: {
      const double A = dx * dx + dy * dy;
      if (A <= 1e-24) {  // along the axis
        if (std::abs(std::hypot(ox, oy) - s.radius) <= tolerance) return false;
        break;
      }
      quadratic(A, 2 * (ox * dx + oy * dy), ox * ox + oy * oy - s.radius * s.radius);
      break;
    }
    case Kind::Sphere:
      quadratic(1, 2 * (ox * dx + oy * dy + oz * dz), ox * ox + oy * oy + oz * oz - s.radius * s.radius);
      break;
    case Kind::Cone: {
      // x^2 + y^2 = r(z)^2 with r(z) = R + z tan(half-angle), both nappes.
      const double k = s.tanAngle, r0 = s.radius + oz * k;
      const double A = dx * dx + dy * dy - dz * dz * k * k;
      if (std::abs(A) <= 1e-12) return false;  // along a generator
      quadratic(A, 2 * (ox * dx + oy * dy - r0 * dz * k), ox * ox + oy * oy - r0 * r0);
      break;
    }
    case Kind::Torus: {
      const IntAna_IntLinTorus intersection(gp_Lin(gp_Pnt(a[0], a[1], a[2]), gp_Dir(dir)), s.torus);
      if (!intersection.IsDone()) return false;
      const double R2 = s.radius * s.radius, r2 = s.minorRadius * s.minorRadius;
      for (int i = 1; i <= intersection.NbPoints() && rootCount < 4; ++i) {
        // Polish the quartic's root along the line: F = (|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2).
        double w = intersection.ParamOnLine(i);
        for (int iteration = 0; iteration < 3; ++iteration) {
          const double x = ox + w * dx, y = oy + w * dy, z = oz + w * dz;
          const double sum = x * x + y * y + z * z + R2 - r2;
          const double F = sum * sum - 4 * R2 * (x * x + y * y);
          const double dF = 4 * sum * (x * dx + y * dy + z * dz) - 8 * R2 * (x * dx + y * dy);
          if (dF == 0) break;
          const double step = F / dF;
          if (!std::isfinite(step) || std::abs(step) > 1e-6 * diagonal) break;
          w -= step;
        }
        roots[rootCount++] = w;
      }
      break;
    }
    case Kind::None:
      return false;
  }
  // OpenCASCADE's rounding decides about a crossing at an end of the segment.
  const double endMargin = 100 * tolerance;
  for (int i = 0; i < rootCount; ++i) {
    const double w = roots[i];
    if (w < -endMargin || w > length + endMargin) continue;
    const gp_XYZ point(a[0] + w * dir.X(), a[1] + w * dir.Y(), a[2] + w * dir.Z());
    // The face lies in its triangles' grown boxes; those holding the point are the ones
    // that classify it.
    near.clear();
    analyticFaceTree[f].atPoint(point, [&](int id) { near.push_back(static_cast<size_t>(id)); });
    if (near.empty()) continue;
    if (w <= endMargin || w >= length - endMargin) return false;
    const double x = ox + w * dx, y = oy + w * dy, z = oz + w * dz;
    // The surface normal (gradient of the implicit equation) and the parameters at the root.
    gp_XYZ normal;
    double u, v;
    if (!s.parameters(x, y, z, tolerance, u, v, normal)) return false;
    const double normalLength = normal.Modulus();
    const double lineNormal = (normal.X() * dx + normal.Y() * dy + normal.Z() * dz);
    // A grazing line: its two crossings merge into a touch that OpenCASCADE may call
    // tangent; leave those to it.
    if (!(std::abs(lineNormal) > 1e-3 * normalLength)) return false;
    // Near a boundary chord OpenCASCADE's classification decides (on the boundary, within
    // the tolerance, the crossing may also belong to the neighbour face): its intersector
    // answers for the face. Elsewhere the parametric triangles do.
    const Domain domain = domainByTriangles(gp_Pnt(point), f, u, v, near.data(), near.size());
    if (domain == Domain::Unsure) return false;
    const bool inside = domain == Domain::In;
    if (!inside) continue;
    found.push_back({w, u, v});
  }
  return true;
}

BrepSolid::Impl::NewtonResult BrepSolid::Impl::newtonCrossing(const Point3& a, const Point3& d, double length,
                                                              int face, const NewtonSeed& seed, double& t,
                                                              gp_Pnt2d& uv) const {
  const NewtonTriangle& triangle = newtonTriangle[seed.triangle];
  const std::array<double, 3>& w = seed.weight;
  double u = w[0] * triangle.uv[0].X() + w[1] * triangle.uv[1].X() + w[2] * triangle.uv[2].X();
  double v = w[0] * triangle.uv[0].Y() + w[1] * triangle.uv[1].Y() + w[2] * triangle.uv[2].Y();
  t = seed.t;
  const gp_XYZ dir(d[0], d[1], d[2]);
  // Far below the 1e-7 x diagonal agreement with OpenCASCADE, above double round-off.
  const double tolerance = 1e-12 * diagonal;
  bool converged = false;
  for (int iteration = 0; iteration < 8 && !converged; ++iteration) {
    gp_Pnt p;
    gp_Vec su, sv;
    faceSurface[face]->D1(u, v, p, su, sv);
    // F = S(u,v) - (a + t d); J = [Su Sv -d]; solve J delta = -F by Cramer's rule.
    const gp_XYZ residual(p.X() - (a[0] + t * d[0]), p.Y() - (a[1] + t * d[1]), p.Z() - (a[2] + t * d[2]));
    if (residual.Modulus() <= tolerance) {
      converged = true;
      break;
    }
    const gp_XYZ cu = su.XYZ(), cv = sv.XYZ(), cd = dir.Reversed();
    const double det = cu.Dot(cv.Crossed(cd));
    // Near-singular: a pole, a degenerate parametrisation or a grazing line.
    if (!(std::abs(det) > 0.05 * cu.Modulus() * cv.Modulus() * length)) return NewtonResult::Unsure;
    const gp_XYZ rhs = residual.Reversed();
    u += rhs.Dot(cv.Crossed(cd)) / det;
    v += cu.Dot(rhs.Crossed(cd)) / det;
    t += cu.Dot(cv.Crossed(rhs)) / det;
    if (!std::isfinite(u) || !std::isfinite(v) || !std::isfinite(t)) return NewtonResult::Unsure;
  }
  if (!converged) return NewtonResult::Unsure;
  // Near an end of the segment OpenCASCADE's own rounding decides whether the crossing
  // counts: leave that to it, as any crossing within the face's band of an end.
  const double endMargin = crossingBand[face] / length;
  if (std::abs(t) <= endMargin || std::abs(1 - t) <= endMargin) return NewtonResult::Unsure;
  // The solution must lie on the seed's own parametric triangle: elsewhere it may be the
  // crossing over a neighbour triangle, and this triangle's own crossing not found.
  const gp_XY p0 = triangle.uv[0].XY(), e1 = triangle.uv[1].XY() - p0, e2 = triangle.uv[2].XY() - p0;
  const gp_XY q = gp_XY(u, v) - p0;
  const double area = e1.Crossed(e2);
  if (area == 0) return NewtonResult::Unsure;
  const double w1 = q.Crossed(e2) / area, w2 = e1.Crossed(q) / area;
  const double slack = -1e-9;
  uv.SetCoord(u, v);
  if (!(w1 >= slack && w2 >= slack && 1 - w1 - w2 >= slack)) return NewtonResult::OffTriangle;
  if (t < 0 || t > 1) return NewtonResult::None;
  return NewtonResult::Crossing;
}

std::vector<BrepSolid::Impl::FaceSpan> BrepSolid::Impl::facesNearSegment(const Point3& a, const Point3& b) const {
  std::vector<FaceSpan> found;
  if (!proxyTree) {
    for (size_t f = 0; f < faces.size(); ++f) found.push_back({static_cast<int>(f), 0.0, 1.0, false});
    return found;
  }
  // Collects the B-rep faces having a proxy triangle whose box, grown by the face's crossing
  // band, meets the segment: the only faces the segment can cross (each face lies within
  // that band of its own triangles). A hit on the face lies in such a grown box, so the
  // union of those boxes' parts of the segment is where to look.
  struct Traversal {
    const Impl& m;
    SegmentBoxTest boxTest;
    Kernel::Segment_3 segment;
    Point3 origin, direction;
    std::vector<int> slot;  // per face: index into `found`, -1 when not found yet
    std::vector<FaceSpan>& found;

    // A triangle of a face without closed form whose grown box the segment meets on [t0, t1].
    void intersection(size_t id, double t0, double t1) {
      const int f = m.proxyFaceOfTriangle[id];
      const double band = m.crossingBand[f];
      // A face left to OpenCASCADE only needs its span: a triangle inside it adds nothing.
      if (slot[f] >= 0 && !found[slot[f]].newtonOnly && found[slot[f]].t0 <= t0 && t1 <= found[slot[f]].t1) return;
      const NewtonTriangle& triangle = m.newtonTriangle[id];
      const Kernel::Triangle_3 t(toK(triangle.node[0]), toK(triangle.node[1]), toK(triangle.node[2]));
      NewtonSeed seed{id, 0, {0, 0, 0}, true};
      bool beside = false;  // near the segment but not crossed, and certainly not crossing it
      if (!CGAL::do_intersect(segment, t)) {
        // Segment/triangle distance: reached at an end of the segment or on an edge of the
        // triangle.
        double nearest = std::min(CGAL::to_double(CGAL::squared_distance(segment.source(), t)),
                                  CGAL::to_double(CGAL::squared_distance(segment.target(), t)));
        for (int e = 0; e < 3; ++e)
          nearest = std::min(nearest, CGAL::to_double(CGAL::squared_distance(segment, Kernel::Segment_3(t[e], t[(e + 1) % 3]))));
        if (nearest > band * band) return;
        seed.crossed = false;
        // The surface over the triangle stays within the face's patch deviation of it, and
        // the face reaches past its boundary chords by less than its band: a segment beside
        // the triangle farther than both cannot cross the face over or next to it.
        const double deviation = m.patchDeviation[f];
        beside = nearest > deviation * deviation && chordsFarFromSegment(triangle, band);
      }
      FaceSpan& span = spanOf(f, t0, t1);
      if (!span.newtonOnly) return;
      span.near.push_back(id);
      if (beside) return;
      // Else the surface over it may bulge onto the segment: Newton iteration from where the
      // line meets the triangle's plane finds that crossing, or the crossing over a
      // neighbour the segment passes through. An oblique triangle may have two crossings
      // over it: the face is left to OpenCASCADE.
      if (!seedOf(triangle, seed)) {
        span.newtonOnly = false;
        span.seeds.clear();
        span.near.clear();
        return;
      }
      span.seeds.push_back(seed);
    }
    FaceSpan& spanOf(int f, double t0, double t1) {
      if (slot[f] < 0) {
        slot[f] = static_cast<int>(found.size());
        found.push_back({f, t0, t1});
      } else {
        found[slot[f]].t0 = std::min(found[slot[f]].t0, t0);
        found[slot[f]].t1 = std::max(found[slot[f]].t1, t1);
      }
      return found[slot[f]];
    }
    static KPoint toK(const gp_Pnt& p) { return KPoint(p.X(), p.Y(), p.Z()); }
    bool chordsFarFromSegment(const NewtonTriangle& triangle, double margin) const {
      for (int k = 0; k < 3; ++k)
        if (triangle.boundaryEdge[k] &&
            CGAL::to_double(CGAL::squared_distance(
                segment, Kernel::Segment_3(toK(triangle.node[k]), toK(triangle.node[(k + 1) % 3])))) <= margin * margin)
          return false;
      return true;
    }
    // Where the segment crosses a regular proxy triangle steeply enough that the line
    // cannot turn tangent to the surface patch over it (the tilt bound, plus 10 degrees).
    bool seedOf(const NewtonTriangle& triangle, NewtonSeed& seed) const {
      const gp_XYZ dir(direction[0], direction[1], direction[2]);
      if (!m.steep(triangle, dir)) return false;
      const gp_XYZ p0 = triangle.node[0].XYZ(), e1 = triangle.node[1].XYZ() - p0, e2 = triangle.node[2].XYZ() - p0;
      // Where the line meets the triangle's plane (Moller-Trumbore): a + t d = p0 + w1 e1 + w2 e2.
      const gp_XYZ pvec = dir.Crossed(e2);
      const double det = e1.Dot(pvec);
      const gp_XYZ s = gp_XYZ(origin[0], origin[1], origin[2]) - p0;
      const double w1 = s.Dot(pvec) / det;
      const gp_XYZ qvec = s.Crossed(e1);
      const double w2 = dir.Dot(qvec) / det;
      seed.t = e2.Dot(qvec) / det;
      seed.weight = {1 - w1 - w2, w1, w2};
      return std::isfinite(seed.t) && std::isfinite(seed.weight[0]);
    }
  };
  Traversal traversal{*this, SegmentBoxTest(a, b - a),
                      Kernel::Segment_3(KPoint(a[0], a[1], a[2]), KPoint(b[0], b[1], b[2])),
                      a, b - a, std::vector<int>(newtonFaceTree.empty() ? 0 : faces.size(), -1), found};
  newtonFaceTree.onSegment(traversal.boxTest,
                           [&](int id, double t0, double t1) { traversal.intersection(static_cast<size_t>(id), t0, t1); });
  // Analytic faces are solved on the whole segment part in their box; their triangles are
  // looked up at the solutions only.
  for (int f : analyticFaces) {
    double t0, t1;
    if (traversal.boxTest.meets(analyticFaceTree[f].box(), 0.0, t0, t1)) found.push_back({f, t0, t1});
  }
  for (int f : facesWithoutTriangles) found.push_back({f, 0.0, 1.0, false, {}});  // in no tree
  return found;
}

std::vector<BoundaryCrossing> BrepSolid::Impl::exactCrossings(const Point3& a, const Point3& b,
                                                              const std::vector<FaceSpan>& candidates) const {
  std::vector<BoundaryCrossing> result;
  if (candidates.empty()) return result;
  const Point3 d = b - a;
  const double length = norm(d);
  const gp_Lin line(toGp(a), gp_Dir(d[0], d[1], d[2]));

  std::unique_ptr<FaceIntersectors> lease;
  {
    std::lock_guard<std::mutex> lock(intersectorMutex);
    if (!idleIntersectors.empty()) {
      lease = std::move(idleIntersectors.back());
      idleIntersectors.pop_back();
    }
  }
  if (!lease) {
    lease = std::make_unique<FaceIntersectors>();
    lease->byFace.resize(faces.size());
    lease->domainByFace.resize(faces.size());
  }
  struct Hit {
    BoundaryCrossing crossing;
    int solid;
  };
  std::vector<Hit> hits;
  // A crossing of face f at w (along the line) and (u, v); its sense from the face's normal.
  auto addHit = [&](int f, double w, double u, double v) {
    gp_Pnt onSurface;
    gp_Vec du, dv;
    faceSurface[f]->D1(u, v, onSurface, du, dv);
    gp_Vec normal = du.Crossed(dv);
    if (faces[f].Orientation() == TopAbs_REVERSED) normal.Reverse();
    const double side = normal.X() * d[0] + normal.Y() * d[1] + normal.Z() * d[2];
    Hit hit;
    hit.crossing.t = w / length;
    hit.crossing.point = a + hit.crossing.t * d;
    hit.crossing.patch = f;
    hit.solid = solidOfFace[f];
    if (normal.Magnitude() <= 1e-12 * du.Magnitude() * dv.Magnitude()) {
      // A pole or an apex: no normal, so the side is read off the classifier just beyond.
      const double step = std::min(1.0 - hit.crossing.t, 1e-7 * diagonal / length);
      hit.crossing.entering = step > 0 && classifyExact(a + (hit.crossing.t + step) * d);
    } else if (side == 0.0) {
      return;
    } else {
      hit.crossing.entering = side < 0;
    }
    hits.push_back(hit);
  };
  std::vector<std::pair<double, gp_Pnt2d>> newtonHits;
  std::vector<LineHit> analyticHits;
  std::vector<size_t> nearSolution;
  for (const FaceSpan& span : candidates) {
    const int f = span.face;
    if (span.newtonOnly && analytic[f].kind != AnalyticSurface::Kind::None) {
      std::vector<LineHit>& found = analyticHits;
      found.clear();
      if (analyticCrossings(a, d, length, f, found, nearSolution, *lease)) {
        for (const LineHit& hit : found) addHit(f, hit.w, hit.u, hit.v);
        continue;
      }
    }
    // Each crossing of the face lies on the surface over one of the triangles near the
    // segment. When each of those is either certified beside the segment or steep enough for
    // one crossing over it, one Newton solve per steep triangle finds them all, and
    // OpenCASCADE's intersector is not needed (no seed at all: the face is not crossed).
    bool solved = span.newtonOnly && analytic[f].kind == AnalyticSurface::Kind::None;
    newtonHits.clear();
    const gp_XYZ direction(d[0], d[1], d[2]);
    for (size_t i = 0; solved && i < span.seeds.size(); ++i) {
      double t;
      gp_Pnt2d uv;
      NewtonResult found = newtonCrossing(a, d, length, f, span.seeds[i], t, uv);
      bool onSeedTriangle = found == NewtonResult::Crossing;
      if (found == NewtonResult::OffTriangle) {
        // A crossing of the line over another steep triangle near the segment: that is the
        // crossing near this seed (the surface cannot fold back between two patches the
        // line crosses steeply), and the seed's own triangle has none.
        found = NewtonResult::Unsure;
        const gp_Pnt point = toGp(a + t * d);
        for (size_t id : span.near) {
          double u = uv.X(), v = uv.Y();
          if (!steep(newtonTriangle[id], direction) || domainByTriangles(point, f, u, v, &id, 1) != Domain::In)
            continue;
          found = t < 0 || t > 1 ? NewtonResult::None : NewtonResult::Crossing;
          break;
        }
      }
      solved = found != NewtonResult::Unsure;
      if (found != NewtonResult::Crossing) continue;
      // The solution lies on a parametric triangle of the face: in the face's domain unless
      // a boundary chord is near. There OpenCASCADE's classification decides: outside, no
      // crossing; on the boundary (within the tolerance) the crossing may belong to the
      // neighbour face, which OpenCASCADE's intersector sorts out.
      double u = uv.X(), v = uv.Y();
      if (!(onSeedTriangle && newtonTriangle[span.seeds[i].triangle].interior) &&
          domainByTriangles(toGp(a + t * d), f, u, v, span.near.data(), span.near.size()) != Domain::In)
        solved = domainOf(*lease, f).Perform(uv) == TopAbs_IN;
      // Two seeds on a shared triangle edge find the same crossing: keep it once.
      if (solved && std::none_of(newtonHits.begin(), newtonHits.end(), [&](const auto& hit) {
            return std::abs(hit.first - t) * length <= 1e-9 * diagonal;
          }))
        newtonHits.emplace_back(t, uv);
    }
    if (solved) {
      for (const auto& [t, uv] : newtonHits) addHit(f, t * length, uv.X(), uv.Y());
      continue;
    }
    auto& intersector = lease->byFace[f];
    if (!intersector) intersector = std::make_unique<IntCurvesFace_Intersector>(faces[f], classifyTolerance);
    intersector->Perform(line, span.t0 * length, span.t1 * length);
    if (!intersector->IsDone()) continue;
    for (int i = 1; i <= intersector->NbPnt(); ++i) {
      if (intersector->Transition(i) == IntCurveSurface_Tangent) continue;
      const double w = intersector->WParameter(i);
      if (w < 0.0 || w > length) continue;
      addHit(f, w, intersector->UParameter(i), intersector->VParameter(i));
    }
  }
  {
    std::lock_guard<std::mutex> lock(intersectorMutex);
    idleIntersectors.push_back(std::move(lease));
  }

  std::sort(hits.begin(), hits.end(), [](const Hit& x, const Hit& y) {
    return x.crossing.t != y.crossing.t ? x.crossing.t < y.crossing.t : x.crossing.patch < y.crossing.patch;
  });
  // Along one solid the segment enters and leaves in turn. Two hits in a row in the same
  // sense are one crossing through the edge two faces share (or a seam) when they are at the
  // same place: keep the first. Farther apart, one of them is wrong (OpenCASCADE misses a
  // crossing or finds a spurious one on grazing B-spline faces, BRepIntCurveSurface_Inter
  // alike): the classifier between them says which one agrees with inside().
  const double sameEdge = 1e-6 * diagonal / length;
  std::vector<int> lastOfSolid(solids.size(), -1);  // index into `kept`
  std::vector<const Hit*> kept;
  for (const Hit& hit : hits) {
    int& last = lastOfSolid[hit.solid];
    if (last >= 0 && kept[last]->crossing.entering == hit.crossing.entering) {
      const Hit& previous = *kept[last];
      if (hit.crossing.t - previous.crossing.t <= sameEdge) continue;
      const bool insideBetween = classifyExact(a + 0.5 * (previous.crossing.t + hit.crossing.t) * d);
      // Entering twice: inside between them means the second is wrong, else the first.
      // Leaving twice: inside between them means the first is wrong, else the second.
      if (insideBetween == hit.crossing.entering) continue;
      kept[last] = nullptr;
    }
    last = static_cast<int>(kept.size());
    kept.push_back(&hit);
  }
  for (const Hit* hit : kept)
    if (hit) result.push_back(hit->crossing);
  return result;
}

// ------------------------------------------------------------------------------------------

BrepSolid::BrepSolid(const TopoDS_Shape& shape, std::string name) : impl_(std::make_unique<Impl>()) {
  impl_->name = std::move(name);
  const std::string what = "input '" + impl_->name + "'";
  try {
    impl_->shape = validatedSolids(shape, what);
    impl_->box = boxOf(impl_->shape);
    impl_->diagonal = impl_->box.diagonal();
    if (!(impl_->diagonal > 0))
      throw InputError(what + " has an empty bounding box: select a solid that encloses a volume");
    impl_->classifyTolerance = 1e-9 * impl_->diagonal;
    impl_->volume = signedVolume(impl_->shape);
    impl_->index();
    impl_->buildProxy();
  } catch (const Standard_Failure& failure) {
    throw InputError(what + " could not be processed by OpenCASCADE (" + failure.GetMessageString() +
                     "): check it with Part > Check geometry and repair it");
  }
}

BrepSolid::~BrepSolid() = default;

namespace {

// Reads a STEP, IGES or BREP file into one shape; InputError naming the input and the file.
TopoDS_Shape readShapeFile(const std::string& path, const std::string& what) {
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
      throw InputError(what + " cannot be read: the file does not exist or is not readable; check the path");
  }
  const std::string ext = lowerExtension(path);
  TopoDS_Shape shape;
  try {
    if (ext == "step" || ext == "stp") {
      STEPControl_Reader reader;
      if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
        throw InputError(what + " is not a readable STEP file: export it again as STEP AP203/AP214 from the CAD tool");
      if (reader.TransferRoots() == 0)
        throw InputError(what + " holds no shape OpenCASCADE can transfer: export it again as STEP AP203/AP214");
      shape = reader.OneShape();
    } else if (ext == "iges" || ext == "igs") {
      IGESControl_Reader reader;
      if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
        throw InputError(what + " is not a readable IGES file: export it again (IGES 5.3, or better STEP) from the CAD tool");
      if (reader.TransferRoots() == 0)
        throw InputError(what + " holds no shape OpenCASCADE can transfer: export it again as IGES 5.3 or STEP");
      shape = reader.OneShape();
    } else if (ext == "brep" || ext == "brp") {
      BRep_Builder builder;
      if (!BRepTools::Read(shape, path.c_str(), builder) || shape.IsNull())
        throw InputError(what + " is not a readable BREP file: write it again with Part > Export (*.brep)");
    } else {
      throw InputError(what + " has an unsupported file type '." + ext +
                       "': give a STEP (.step, .stp), IGES (.iges, .igs) or BREP (.brep, .brp) file");
    }
  } catch (const Standard_Failure& failure) {
    throw InputError(what + " could not be read (" + std::string(failure.GetMessageString()) +
                     "): export it again from the CAD tool");
  }
  return shape;
}

// Errors of the constructor name the input; loaders of files name the file as well, since a
// user may have several inputs with similar names.
template <class Action>
auto namingTheFile(const std::string& name, const std::string& what, Action action) {
  try {
    return action();
  } catch (const InputError& e) {
    std::string message = e.what();
    const std::string prefix = "input '" + name + "'";
    if (message.rfind(prefix, 0) == 0 && what != prefix) message = what + message.substr(prefix.size());
    throw InputError(message);
  }
}

}  // namespace

TopoDS_Shape readBrepText(const std::string& text, const std::string& what, const std::string& fix) {
  TopoDS_Shape shape;
  try {
    std::istringstream stream(text);
    BRep_Builder builder;
    BRepTools::Read(shape, stream, builder);
  } catch (const Standard_Failure& failure) {
    throw InputError(what + " cannot be read by OpenCASCADE (" + std::string(failure.GetMessageString()) + ")" + fix);
  }
  if (shape.IsNull()) throw InputError(what + " cannot be read by OpenCASCADE" + fix);
  return shape;
}

static TopoDS_Shape readSolidBrepText(const std::string& text, const std::string& name) {
  return readBrepText(text, "input '" + name + "' (BREP text)", ": pass Shape.exportBrepToString() of a solid");
}

BrepSolid::Loaded BrepSolid::load(const TopoDS_Shape& shape, const std::string& name, Grouping grouping,
                                  const std::string& path) {
  const std::string what = describe(name, path);
  Loaded loaded;
  SolidPieces pieces;
  try {
    pieces = solidPieces(shape, what);
  } catch (const Standard_Failure& failure) {
    throw InputError(what + " could not be processed by OpenCASCADE (" + failure.GetMessageString() +
                     "): check it with Part > Check geometry and repair it");
  }
  for (const std::string& s : pieces.skipped)
    loaded.warnings.push_back(what + ": " + s + " bounds no volume and was left out; close it (Part > Shape builder) "
                              "if it should be meshed");
  if (grouping == Grouping::Together || pieces.solids.size() == 1) {
    loaded.solids.push_back(namingTheFile(name, what, [&] { return std::make_shared<BrepSolid>(compoundOf(pieces.solids), name); }));
    return loaded;
  }
  for (size_t i = 0; i < pieces.solids.size(); ++i) {
    const std::string solidName = name + "#" + std::to_string(i + 1);
    loaded.solids.push_back(namingTheFile(solidName, describe(solidName, path),
                                          [&] { return std::make_shared<BrepSolid>(pieces.solids[i], solidName); }));
  }
  return loaded;
}

BrepSolid::Loaded BrepSolid::loadFile(const std::string& path, const std::string& name, Grouping grouping) {
  return load(readShapeFile(path, describe(name, path)), name, grouping, path);
}

BrepSolid::Loaded BrepSolid::loadBrepText(const std::string& text, const std::string& name, Grouping grouping) {
  return load(readSolidBrepText(text, name), name, grouping);
}

std::shared_ptr<BrepSolid> BrepSolid::fromFile(const std::string& path, const std::string& name) {
  const std::string what = describe(name, path);
  const TopoDS_Shape shape = readShapeFile(path, what);
  return namingTheFile(name, what, [&] { return std::make_shared<BrepSolid>(shape, name); });
}

std::shared_ptr<BrepSolid> BrepSolid::fromBrepText(const std::string& text, const std::string& name) {
  return std::make_shared<BrepSolid>(readSolidBrepText(text, name), name);
}

const std::string& BrepSolid::name() const { return impl_->name; }
Bbox BrepSolid::bbox() const { return impl_->box; }
double BrepSolid::volume() const { return impl_->volume; }
const TopoDS_Shape& BrepSolid::shape() const { return impl_->shape; }
int BrepSolid::faceCount() const { return static_cast<int>(impl_->faces.size()); }
int BrepSolid::edgeCount() const { return static_cast<int>(impl_->edges.size()); }
const TopoDS_Face& BrepSolid::face(int index) const { return impl_->faces.at(index); }
const TopoDS_Edge& BrepSolid::edge(int index) const { return impl_->edges.at(index); }
const std::vector<int>& BrepSolid::facesOfEdge(int edge) const { return impl_->edgeFaces.at(edge); }
const BrepSolid::ProxyInfo& BrepSolid::proxyInfo() const { return impl_->proxy; }

bool BrepSolid::insideExact(const Point3& p) const {
  if (!impl_->box.contains(p, impl_->classifyTolerance)) return false;
  try {
    return impl_->classifyExact(p);
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to classify a point against input '" + impl_->name + "' (" +
                failure.GetMessageString() + "): check the solid with Part > Check geometry");
  }
}

bool BrepSolid::inside(const Point3& p) const {
  if (!impl_->box.contains(p, impl_->classifyTolerance)) return false;
  if (impl_->proxySide) {
    const KPoint q(p[0], p[1], p[2]);
    // Farther from the tessellation than it can be from the B-rep: both sides agree.
    if (impl_->proxyTrusted(q)) return (*impl_->proxySide)(q) == CGAL::ON_BOUNDED_SIDE;
  }
  return insideExact(p);
}

BoundaryProjection BrepSolid::project(const Point3& p) const {
  const Impl& m = *impl_;
  const gp_Pnt q = toGp(p);
  BoundaryProjection best;
  try {
    if (!m.proxyTree) {
      for (int f = 0; f < faceCount(); ++f) {
        const BoundaryProjection c = m.projectOnFace(q, f);
        if (c.distance < best.distance) best = c;
      }
      return best;
    }
    // The true boundary is within `h` of the proxy, so a face can hold the nearest point only
    // if its proxy triangles come within d0 + 2h, d0 being the distance to the proxy.
    const KPoint kq(p[0], p[1], p[2]);
    const double h = m.proxy.deflection;
    const double d0 = std::sqrt(CGAL::to_double(m.proxyTree->squared_distance(kq)));
    const double reach = d0 + 2 * h;
    std::vector<ProxyTree::Primitive_id> near;
    m.proxyTree->all_intersected_primitives(Kernel::Sphere_3(kq, reach * reach), std::back_inserter(near));
    std::map<int, double> faceProxyDistance;
    for (const ProxyTree::Primitive_id& id : near) {
      const int f = m.proxyFaceOfTriangle[static_cast<size_t>(id)];
      const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(kq, m.proxyTriangle(id))));
      auto [it, fresh] = faceProxyDistance.emplace(f, d);
      if (!fresh) it->second = std::min(it->second, d);
    }
    std::vector<std::pair<double, int>> candidates;
    for (const auto& [f, d] : faceProxyDistance) candidates.emplace_back(d, f);
    std::sort(candidates.begin(), candidates.end());
    for (const auto& [proxyDistance, f] : candidates) {
      if (proxyDistance - h > best.distance) break;  // cannot beat the best exact answer
      const BoundaryProjection c = m.projectOnFace(q, f);
      if (c.distance < best.distance) best = c;
    }
    // Faces without triangles are not in the tree: check them exactly.
    if (!m.proxy.usable)
      for (int f = 0; f < faceCount(); ++f)
        if (!faceProxyDistance.count(f)) {
          TopLoc_Location loc;
          if (!BRep_Tool::Triangulation(m.faces[f], loc).IsNull()) continue;
          const BoundaryProjection c = m.projectOnFace(q, f);
          if (c.distance < best.distance) best = c;
        }
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to project a point onto input '" + m.name + "' (" + failure.GetMessageString() +
                ")");
  }
  return best;
}

std::vector<BoundaryCrossing> BrepSolid::crossings(const Point3& a, const Point3& b) const {
  const Impl& m = *impl_;
  if (distance(a, b) == 0.0) return {};
  CGAL::Bbox_3 box(m.box.min[0], m.box.min[1], m.box.min[2], m.box.max[0], m.box.max[1], m.box.max[2]);
  if (!SegmentBoxTest(a, b - a).meets(box, m.classifyTolerance)) return {};
  try {
    return m.exactCrossings(a, b, m.facesNearSegment(a, b));
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to intersect a segment with input '" + m.name + "' (" +
                failure.GetMessageString() + "): check the solid with Part > Check geometry");
  }
}

BoundaryProjection BrepSolid::projectOnEdge(const Point3& p, int edgeIndex) const {
  const Impl& m = *impl_;
  BoundaryProjection result;
  try {
    BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(toGp(p)).Vertex(), m.edges.at(edgeIndex),
                                    Extrema_ExtFlag_MIN);
    if (!dist.IsDone() || dist.NbSolution() == 0) return result;
    result.point = toPoint3(dist.PointOnShape2(1));
    result.distance = dist.Value();
    const std::vector<int>& adjacent = m.edgeFaces[edgeIndex];
    result.patch = adjacent.empty() ? -1 : adjacent.front();
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to project a point onto an edge of input '" + m.name + "' (" +
                failure.GetMessageString() + ")");
  }
  return result;
}

std::vector<BoundarySample> BrepSolid::boundarySamples(double spacing) const {
  const Impl& m = *impl_;
  // Candidates are face-interior points: interior tessellation nodes and the parametric
  // centroids of tessellation triangles, evaluated on the exact surface. Points on edges are
  // left out on purpose: the two faces of an edge would give near-duplicate seeds there, and
  // the edges are seeded by the features anyway.
  struct Candidate {
    gp_Pnt point;
    gp_Vec normal;
  };
  const bool thin = spacing > 0 && std::isfinite(spacing);
  const double cell = thin ? spacing : 1.0;
  auto cellOf = [&](const gp_Pnt& p) {
    return std::array<int64_t, 3>{static_cast<int64_t>(std::floor(p.X() / cell)),
                                  static_cast<int64_t>(std::floor(p.Y() / cell)),
                                  static_cast<int64_t>(std::floor(p.Z() / cell))};
  };
  std::map<std::array<int64_t, 3>, std::vector<Point3>> accepted;
  auto farFromAccepted = [&](const gp_Pnt& p) {
    if (!thin) return true;
    const auto c = cellOf(p);
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = accepted.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == accepted.end()) continue;
          for (const Point3& a : it->second)
            if (distance(a, toPoint3(p)) < 0.5 * spacing) return false;
        }
    return true;
  };

  std::vector<BoundarySample> samples;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const TopoDS_Face& face = m.faces[f];
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    BRepAdaptor_Surface surface(face, Standard_True);
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    std::vector<gp_Pnt2d> uvs;
    std::vector<gp_Vec> fallbackNormals;  // triangle normals where the surface normal degenerates
    if (!tri.IsNull() && tri->HasUVNodes()) {
      // Interior nodes are those not on any triangle edge that is used once (boundary).
      std::map<std::pair<int, int>, int> use;
      for (int t = 1; t <= tri->NbTriangles(); ++t) {
        int a, b, c;
        tri->Triangle(t).Get(a, b, c);
        for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) ++use[{std::min(u, v), std::max(u, v)}];
      }
      std::vector<char> onBoundary(tri->NbNodes() + 1, 0);
      for (const auto& [e, n] : use)
        if (n == 1) onBoundary[e.first] = onBoundary[e.second] = 1;
      const gp_Trsf trsf = loc.Transformation();
      for (int n = 1; n <= tri->NbNodes(); ++n)
        if (!onBoundary[n]) {
          uvs.push_back(tri->UVNode(n));
          fallbackNormals.emplace_back(0, 0, 0);
        }
      for (int t = 1; t <= tri->NbTriangles(); ++t) {
        int a, b, c;
        tri->Triangle(t).Get(a, b, c);
        const gp_Pnt2d ua = tri->UVNode(a), ub = tri->UVNode(b), uc = tri->UVNode(c);
        uvs.emplace_back((ua.X() + ub.X() + uc.X()) / 3, (ua.Y() + ub.Y() + uc.Y()) / 3);
        const gp_Pnt pa = tri->Node(a).Transformed(trsf), pb = tri->Node(b).Transformed(trsf),
                     pc = tri->Node(c).Transformed(trsf);
        gp_Vec n = gp_Vec(pa, pb).Crossed(gp_Vec(pa, pc));
        if (reversed) n.Reverse();
        fallbackNormals.push_back(n);
      }
    } else {
      // No tessellation for this face: its parametric middle, if that lies on the face.
      double u0, u1, v0, v1;
      BRepTools::UVBounds(face, u0, u1, v0, v1);
      uvs.emplace_back(0.5 * (u0 + u1), 0.5 * (v0 + v1));
      fallbackNormals.emplace_back(0, 0, 0);
    }

    std::vector<Candidate> candidates;
    for (size_t i = 0; i < uvs.size(); ++i) {
      gp_Pnt p;
      gp_Vec du, dv;
      surface.D1(uvs[i].X(), uvs[i].Y(), p, du, dv);
      gp_Vec n = du.Crossed(dv);
      if (reversed) n.Reverse();
      if (n.Magnitude() <= 1e-12 * std::max(du.Magnitude() * dv.Magnitude(), 1e-300)) n = fallbackNormals[i];
      if (n.Magnitude() <= 0) continue;
      candidates.push_back({p, n.Normalized()});
    }
    bool faceHasSample = false;
    for (const Candidate& c : candidates) {
      if (!farFromAccepted(c.point)) continue;
      samples.push_back({toPoint3(c.point), toPoint3(gp_Pnt(c.normal.XYZ())), static_cast<int>(f)});
      if (thin) accepted[cellOf(c.point)].push_back(toPoint3(c.point));
      faceHasSample = true;
    }
    if (!faceHasSample && !candidates.empty()) {
      // Every face gets a seed, even one smaller than the spacing: take its candidate farthest
      // from the seeds already placed, so it does not crowd them.
      size_t bestIndex = 0;
      double bestGap = -1;
      for (size_t i = 0; i < candidates.size(); ++i) {
        double gap = std::numeric_limits<double>::infinity();
        const auto cc = cellOf(candidates[i].point);
        for (int64_t dx = -1; dx <= 1; ++dx)
          for (int64_t dy = -1; dy <= 1; ++dy)
            for (int64_t dz = -1; dz <= 1; ++dz) {
              auto it = accepted.find({cc[0] + dx, cc[1] + dy, cc[2] + dz});
              if (it == accepted.end()) continue;
              for (const Point3& a : it->second) gap = std::min(gap, distance(a, toPoint3(candidates[i].point)));
            }
        if (gap > bestGap) {
          bestGap = gap;
          bestIndex = i;
        }
      }
      const Candidate& c = candidates[bestIndex];
      samples.push_back({toPoint3(c.point), toPoint3(gp_Pnt(c.normal.XYZ())), static_cast<int>(f)});
      if (thin) accepted[cellOf(c.point)].push_back(toPoint3(c.point));
    }
  }
  return samples;
}

}  // namespace oraclemesh
