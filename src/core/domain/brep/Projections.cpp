// Nearest boundary points: onto the faces (candidates from the proxy, answered by
// OpenCASCADE) and onto one edge.
#include "domain/brep/BrepSolidImpl.h"

#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopLoc_Location.hxx>

#include <algorithm>
#include <map>

#include "Error.h"
#include "domain/OpenCascadeWork.h"
#include "domain/brep/OcctConversions.h"

namespace oraclemesh {

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

BoundaryProjection BrepSolid::project(const Point3& p) const {
  const Impl& m = *impl_;
  const OpenCascadeWork working(m.name);
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

BoundaryProjection BrepSolid::projectOnEdge(const Point3& p, int edgeIndex) const {
  const Impl& m = *impl_;
  const OpenCascadeWork working(m.name);
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

}  // namespace oraclemesh
