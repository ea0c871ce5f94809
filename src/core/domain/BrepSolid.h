#pragma once
// A B-rep solid input (STEP, IGES, BREP file or BREP text from FreeCAD), answered exactly by
// OpenCASCADE where it matters and through a tessellation proxy everywhere else.
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "domain/BrepTopology.h"
#include "domain/Source.h"

namespace oraclemesh {

class RunControl;
struct ValidatedSolids;

// The shape in BREP text (FreeCAD's Shape.exportBrepToString()). An unreadable text is an
// InputError "<what> cannot be read by OpenCASCADE (<reason>)<fix>".
TopoDS_Shape readBrepText(const std::string& text, const std::string& what, const std::string& fix);

class BrepSolid : public Source, public BrepTopology {
 public:
  // How the solids of one file (or BREP text) become oracle inputs: one input per solid in the
  // order the file lists them, named "<name>#1".."<name>#N" (just "<name>" for a single
  // solid), or all of them as one input "<name>".
  enum class Grouping { Separate, Together };
  struct Loaded {
    std::vector<std::shared_ptr<BrepSolid>> solids;  // highest priority first
    // Open shells (and loose faces) left out because solids remain: one sentence each,
    // naming the input, the file, the shell's place in the file and its free edges.
    std::vector<std::string> warnings;
    // The largest length uncertainty a STEP file declares, in model units (0: none declared,
    // or not a STEP file): with the shapes' own tolerances, the CAD's idea of touching.
    double declared_uncertainty = 0;
  };
  // Reads a STEP (.step/.stp), IGES (.iges/.igs) or BREP (.brep/.brp) file. A closed shell
  // (or faces that sew into one) is made a solid. Open shells beside at least one solid are
  // left out with a warning; an input with no solid left, a solid with an open boundary or an
  // unreadable file is an InputError naming `name` and the file.
  static Loaded loadFile(const std::string& path, const std::string& name, Grouping grouping);
  // BREP text as written by OpenCASCADE's BRepTools::Write (FreeCAD: Shape.exportBrepToString()).
  static Loaded loadBrepText(const std::string& text, const std::string& name, Grouping grouping);
  // The same in a helper process (domain/brep/IsolatedReading.h): OpenCASCADE reads and
  // checks the file there, so its crash or hang on a damaged file becomes an InputError naming
  // the file, and `control`'s time limit and cancel hold while it reads (progress is reported
  // as phase "load" at `progress`). The job pipeline loads every B-rep this way.
  static Loaded loadFileIsolated(const std::string& path, const std::string& name, Grouping grouping,
                                 const RunControl& control, double progress);
  static Loaded loadBrepTextIsolated(const std::string& text, const std::string& name, Grouping grouping,
                                     const RunControl& control, double progress);
  // Whether a new solid tessellates its shape (BRepMesh) or takes the triangles the shape
  // carries: the helper process tessellates, and BRepMesh on a damaged shape can run away
  // (fuzz_brep found one), so the caller must not run it again outside the helper. Faces
  // that carry no triangles are answered by OpenCASCADE's exact queries either way.
  enum class Tessellation { Make, Reuse };
  // `path` only names the file in messages.
  static Loaded load(const TopoDS_Shape& shape, const std::string& name, Grouping grouping,
                     const std::string& path = "", Tessellation tessellation = Tessellation::Make);
  // All solids of the file or text as this one input; open shells beside solids are an error
  // here (there is nowhere to put the warning): use loadFile / loadBrepText to skip them.
  static std::shared_ptr<BrepSolid> fromFile(const std::string& path, const std::string& name);
  static std::shared_ptr<BrepSolid> fromBrepText(const std::string& text, const std::string& name);
  // Takes a shape holding one or more solids (or closed shells); every part must bound a volume.
  BrepSolid(const TopoDS_Shape& shape, std::string name, Tessellation tessellation = Tessellation::Make);
  ~BrepSolid() override;

  const std::string& name() const override;
  Bbox bbox() const override;
  bool inside(const Point3& p) const override;
  BoundaryProjection project(const Point3& p) const override;
  // The foot on the face's surface (a per-face ShapeAnalysis_Surface) where it lies inside the
  // face; else OpenCASCADE's distance to the trimmed face.
  BoundaryProjection projectOnPatch(const Point3& p, int face) const override;
  std::vector<BoundarySample> boundarySamples(double spacing) const override;
  // Exact crossings, face by face. A face on a plane, cylinder, cone, sphere or torus whose
  // triangles' band-grown boxes the segment meets is intersected in closed form, its roots
  // classified by the face's parametric triangles. Other faces whose triangles come within
  // their band are solved by Newton iteration from the triangles the segment crosses or
  // passes steeply. OpenCASCADE (IntCurvesFace_Intersector) answers for a face where a root
  // lies near the face's boundary or an end of the segment, a line grazes the surface, a
  // triangle near the segment is too oblique, and for faces without triangles.
  // patch = face index; `entering` from the face's outward normal. Tangential touches are
  // dropped; a crossing through an edge shared by two faces is reported once (for the face
  // hit first).
  std::vector<BoundaryCrossing> crossings(const Point3& a, const Point3& b) const override;
  double volume() const override;

  // This solid itself: the faces, edges and shape the feature and planar-face layers read.
  const BrepTopology* brepTopology() const override;

  // BrepTopology (domain/BrepTopology.h); name() and bbox() above serve both bases.
  const TopoDS_Shape& shape() const override;
  BoundaryProjection projectOnEdge(const Point3& p, int edge) const override;
  int faceCount() const override;
  int edgeCount() const override;
  const TopoDS_Face& face(int index) const override;
  const TopoDS_Edge& edge(int index) const override;
  const std::vector<int>& facesOfEdge(int edge) const override;

  // How the proxy and the exact answers are chosen; exposed for tests and the report.
  struct ProxyInfo {
    bool usable = false;          // false: every inside() query goes to OpenCASCADE
    size_t triangles = 0;         // in the tessellation proxy
    double deflection = 0;        // deviation proxy <-> B-rep, measured (>= BRepMesh's own)
    double exactBand = 0;         // inside(): proxy answer always taken farther than this
                                  // from it (nearer, per-face bands decide)
    int64_t unpairedEdges = 0;    // tessellation edges used an odd number of times (gaps)
  };
  const ProxyInfo& proxyInfo() const;
  // The exact answer, bypassing the proxy, for callers that need it near the boundary: the
  // side of the nearest analytic face where that is proven (Classification.cpp), else
  // OpenCASCADE's.
  bool insideExact(const Point3& p) const;
  // OpenCASCADE's answer alone (BRepClass3d_SolidClassifier per solid): the reference for tests.
  bool insideByOpenCascade(const Point3& p) const;
  // The side of the nearest analytic face where that is proven, else nothing (exposed for tests).
  std::optional<bool> insideByNearestAnalyticFace(const Point3& p) const;

 private:
  // The solids load() has checked and measured already (the public constructor checks them).
  BrepSolid(const ValidatedSolids& solids, std::string name, Tessellation tessellation);
  void setUp(const ValidatedSolids& solids, Tessellation tessellation);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace oraclemesh
