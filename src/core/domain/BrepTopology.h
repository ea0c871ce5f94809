#pragma once
// What the layers above the domain (features, refine, job) read of a B-rep input: its
// OpenCASCADE shape, its faces and edges by index, the faces that meet at an edge and the
// exact projection onto an edge, with the input's name and box for messages and tolerances.
// Source::brepTopology() hands it out (nullptr for inputs that are no B-rep); BrepSolid
// implements it.
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <string>
#include <vector>

#include "Geometry.h"
#include "domain/Source.h"

namespace oraclemesh {

class BrepTopology {
 public:
  virtual ~BrepTopology() = default;

  // The input's name as the user gave it and its bounding box, as its Source's.
  virtual const std::string& name() const = 0;
  virtual Bbox bbox() const = 0;
  // The validated shape: a solid or a compound of solids. Face/edge indices used in
  // patches and features are 1-based TopExp::MapShapes indices minus one.
  virtual const TopoDS_Shape& shape() const = 0;
  virtual int faceCount() const = 0;
  virtual int edgeCount() const = 0;
  // Face / edge by 0-based index (TopExp::MapShapes order on shape()).
  virtual const TopoDS_Face& face(int index) const = 0;
  virtual const TopoDS_Edge& edge(int index) const = 0;
  // 0-based indices of the faces adjacent to an edge (one face for a free edge; a seam edge
  // lists its face once).
  virtual const std::vector<int>& facesOfEdge(int edge) const = 0;
  // Distance from p to the nearest point of edge `edge` (0-based), with that point.
  // `patch` of the result is the first face (0-based) adjacent to the edge.
  virtual BoundaryProjection projectOnEdge(const Point3& p, int edge) const = 0;
};

}  // namespace oraclemesh
