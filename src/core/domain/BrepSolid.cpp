// The B-rep input: validation and indexing at construction, and the topology accessors. The
// queries are defined by job in domain/brep/ (see BrepSolidImpl.h).
#include "domain/brep/BrepSolidImpl.h"

#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>

#include "Error.h"
#include "domain/CoordinateRange.h"
#include "domain/OpenCascadeWork.h"
#include "domain/brep/FiniteGeometry.h"
#include "domain/brep/SolidChecks.h"

namespace oraclemesh {

BrepSolid::BrepSolid(const TopoDS_Shape& shape, std::string name, Tessellation tessellation)
    : impl_(std::make_unique<Impl>()) {
  impl_->name = std::move(name);
  const std::string what = "input '" + impl_->name + "'";
  const OpenCascadeWork working(impl_->name);
  try {
    requireFiniteGeometry(shape, what);
    setUp(validatedSolids(shape, what), tessellation);
  } catch (const Standard_Failure& failure) {
    throw InputError(what + " could not be processed by OpenCASCADE (" + failure.GetMessageString() +
                     "): check it with Part > Check geometry and repair it");
  }
}

BrepSolid::BrepSolid(const ValidatedSolids& solids, std::string name, Tessellation tessellation)
    : impl_(std::make_unique<Impl>()) {
  impl_->name = std::move(name);
  const OpenCascadeWork working(impl_->name);
  try {
    setUp(solids, tessellation);
  } catch (const Standard_Failure& failure) {
    throw InputError("input '" + impl_->name + "' could not be processed by OpenCASCADE (" +
                     failure.GetMessageString() + "): check it with Part > Check geometry and repair it");
  }
}

void BrepSolid::setUp(const ValidatedSolids& solids, Tessellation tessellation) {
  const std::string what = "input '" + impl_->name + "'";
  impl_->shape = solids.shape;
  impl_->box = boxOf(impl_->shape);
  impl_->diagonal = impl_->box.diagonal();
  if (!(impl_->diagonal > 0))
    throw InputError(what + " has an empty bounding box: select a solid that encloses a volume");
  requireCoordinateRange(impl_->box, what);
  impl_->classifyTolerance = 1e-9 * impl_->diagonal;
  impl_->volume = solids.volume;
  impl_->index();
  impl_->buildProxy(tessellation == Tessellation::Make);
}

BrepSolid::~BrepSolid() = default;

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
const BrepTopology* BrepSolid::brepTopology() const { return this; }

}  // namespace oraclemesh
