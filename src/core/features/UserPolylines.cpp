#include "features/UserPolylines.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "Error.h"
#include "domain/BrepSolid.h"

// OpenCASCADE after the project headers (its Handle macro breaks CGAL's).
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>

namespace oraclemesh {

namespace {

std::string where(size_t polyline, const Point3& p) {
  std::ostringstream out;
  out << "features.polylines[" << polyline << "] leaves the meshed domain near (" << p[0] << ", " << p[1] << ", "
      << p[2] << "): draw it inside or on the parts (not in a cut region or outside every input)";
  return out.str();
}

std::string pointText(const Point3& p) {
  std::ostringstream out;
  out << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
  return out.str();
}

// Before anything is sampled: a point far outside the inputs would give billions of samples,
// and an exact edge the points do not lie on (another edge's BREP) would pull the mesh nodes
// of this polyline somewhere else, which the refinement cannot satisfy.
void checkPolyline(size_t index, const std::vector<Point3>& points, const HierarchicalOracle& oracle,
                   const UserCurve* exact) {
  const Bbox& box = oracle.bbox();
  const double slack = 1e-6 * oracle.diagonal();
  const std::string where = "features.polylines[" + std::to_string(index) + "]";
  for (size_t k = 0; k < points.size(); ++k) {
    const Point3& p = points[k];
    for (int a = 0; a < 3; ++a)
      if (!(p[a] >= box.min[a] - slack && p[a] <= box.max[a] + slack))
        throw InputError(where + " leaves the meshed domain: point " + std::to_string(k) + " " + pointText(p) +
                         " lies outside the bounding box of the inputs (" + pointText(box.min) + " to " +
                         pointText(box.max) + "): draw the polyline on or inside the parts, in model units (mm)");
  }
  if (!exact) return;
  // FreeCAD samples the points on the edge itself: they lie on it up to OpenCASCADE's
  // precision. A thousandth of the model is generous for any sampling and still catches a
  // BREP that belongs to another edge.
  const double onEdge = 1e-3 * oracle.diagonal();
  for (size_t k = 0; k < points.size(); ++k) {
    const double off = distance(points[k], exact->nearest(points[k]));
    if (!(off <= onEdge))
      throw InputError(where + " point " + std::to_string(k) + " " + pointText(points[k]) + " is " +
                       std::to_string(off) + " away from the edge in " + where +
                       ".brep: the brep must be the edge the points were sampled from (or leave 'brep' out)");
  }
}

}  // namespace

FeatureGraph userPolylineFeatures(const std::vector<std::vector<Point3>>& polylines, const HierarchicalOracle& oracle,
                                  double maxSegmentLength,
                                  const std::vector<std::shared_ptr<const UserCurve>>& curves) {
  FeatureGraph graph;
  const double onBoundary = 1e-6 * oracle.diagonal();
  for (size_t i = 0; i < polylines.size(); ++i) {
    const std::vector<Point3>& in = polylines[i];
    const UserCurve* exact = i < curves.size() ? curves[i].get() : nullptr;
    checkPolyline(i, in, oracle, exact);
    // Each given segment is a polyline of its own: Mesh_3 keeps polyline ends as vertices but
    // may cut across a kink in the middle of a polyline.
    for (size_t k = 0; k + 1 < in.size(); ++k) {
      FeaturePolyline out;
      out.user = static_cast<int>(i);
      // Bounded: the points are inside the model's box and the edge size is at least a
      // millionth of it (ResolvedCriteria).
      const double count = std::ceil(distance(in[k], in[k + 1]) / maxSegmentLength);
      if (!(count <= 1e7))
        throw InputError("features.polylines[" + std::to_string(i) + "] segment " + std::to_string(k) +
                         " would need " + std::to_string(count) + " pieces of the edge size: raise edge_size");
      const int pieces = std::max(1, static_cast<int>(count));
      for (int j = 0; j <= pieces; ++j)
        out.points.push_back(j == pieces ? in[k + 1] : in[k] + (double(j) / pieces) * (in[k + 1] - in[k]));
      // Every vertex and segment middle inside the composite domain or on its boundary.
      for (size_t m = 0; m < out.points.size(); ++m) {
        std::vector<Point3> probes{out.points[m]};
        if (m + 1 < out.points.size()) probes.push_back(0.5 * (out.points[m] + out.points[m + 1]));
        for (const Point3& probe : probes) {
          const Point3 p = exact ? exact->nearest(probe) : probe;
          if (oracle.label(p) == 0 && oracle.projectOnBoundary(p).distance > onBoundary) throw InputError(where(i, p));
        }
      }
      graph.polylines.push_back(std::move(out));
    }
  }
  return graph;
}

struct UserCurve::Data {
  TopoDS_Edge edge;
  std::string where;
};

UserCurve::UserCurve(std::unique_ptr<Data> data) : data_(std::move(data)) {}
UserCurve::~UserCurve() = default;

std::shared_ptr<const UserCurve> UserCurve::fromBrep(const std::string& text, const std::string& where) {
  const std::string fix = ": give BREP text of one edge (Part.Edge.exportBrepToString()) or leave 'brep' out";
  const TopoDS_Shape shape = readBrepText(text, where, fix);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(shape, TopAbs_EDGE, edges);
  if (edges.Extent() != 1) throw InputError(where + " holds " + std::to_string(edges.Extent()) + " edges" + fix);
  const TopoDS_Edge edge = TopoDS::Edge(edges(1));
  if (BRep_Tool::Degenerated(edge)) throw InputError(where + " is a degenerate edge (a point)" + fix);
  auto data = std::make_unique<Data>();
  data->edge = edge;
  data->where = where;
  return std::shared_ptr<const UserCurve>(new UserCurve(std::move(data)));
}

Point3 UserCurve::nearest(const Point3& p) const {
  try {
    // A fresh query per point: OpenCASCADE's curve adaptors cache evaluations, so sharing one
    // between threads would not be safe.
    BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(gp_Pnt(p[0], p[1], p[2])).Vertex(), data_->edge,
                                    Extrema_ExtFlag_MIN);
    if (dist.IsDone() && dist.NbSolution() > 0) {
      const gp_Pnt q = dist.PointOnShape2(1);
      return {q.X(), q.Y(), q.Z()};
    }
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to project a point onto the edge of " + data_->where + " (" +
                failure.GetMessageString() + ")");
  }
  throw Error("OpenCASCADE found no point of the edge of " + data_->where + " near (" + std::to_string(p[0]) + ", " +
              std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")");
}

}  // namespace oraclemesh
