#pragma once
// A B-rep solid input (STEP, BREP file or BREP text from FreeCAD), answered exactly by
// OpenCASCADE where it matters and through a tessellation proxy everywhere else.
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <memory>
#include <string>
#include <vector>

#include "domain/Source.h"

namespace oraclemesh {

class BrepSolid : public Source {
 public:
  // Reads a STEP (.step/.stp) or BREP (.brep/.brp) file. All solids of the file form this
  // one input. A closed shell without a solid is made a solid; an open shell, a file with no
  // solid or an unreadable file is an InputError naming `name` and the file.
  static std::shared_ptr<BrepSolid> fromFile(const std::string& path, const std::string& name);
  // BREP text as written by OpenCASCADE's BRepTools::Write (FreeCAD: Shape.exportBrepToString()).
  static std::shared_ptr<BrepSolid> fromBrepText(const std::string& text, const std::string& name);
  // Takes a shape holding one or more solids (or closed shells); validates it as above.
  BrepSolid(const TopoDS_Shape& shape, std::string name);
  ~BrepSolid() override;

  const std::string& name() const override;
  Bbox bbox() const override;
  bool inside(const Point3& p) const override;
  BoundaryProjection project(const Point3& p) const override;
  std::vector<BoundarySample> boundarySamples(double spacing) const override;
  // Exact crossings: the faces whose proxy triangles come within their band of the segment
  // are intersected with the segment's line by OpenCASCADE (IntCurvesFace_Intersector);
  // every face when the proxy has none. patch = face index; `entering` from the face's
  // outward normal. Tangential touches are dropped; a crossing through an edge shared by two
  // faces is reported once (for the face hit first).
  std::vector<BoundaryCrossing> crossings(const Point3& a, const Point3& b) const override;
  double volume() const override;

  // The validated shape: a solid or a compound of solids. Face/edge indices used in
  // patches and features are 1-based TopExp::MapShapes indices minus one.
  const TopoDS_Shape& shape() const;
  // Distance from p to the nearest point of B-rep edge `edge` (0-based), with that point.
  // `patch` of the result is the first face (0-based) adjacent to the edge.
  BoundaryProjection projectOnEdge(const Point3& p, int edge) const;
  int faceCount() const;
  int edgeCount() const;
  // Face / edge by 0-based index (TopExp::MapShapes order on shape()).
  const TopoDS_Face& face(int index) const;
  const TopoDS_Edge& edge(int index) const;
  // 0-based indices of the faces adjacent to an edge (one face for a free edge; a seam edge
  // lists its face once).
  const std::vector<int>& facesOfEdge(int edge) const;

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
  // The OpenCASCADE answer alone (BRepClass3d_SolidClassifier per solid), bypassing the
  // proxy: the reference for tests and for callers that need it near the boundary.
  bool insideExact(const Point3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace oraclemesh
