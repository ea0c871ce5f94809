// Which points are inside: the tessellation proxy's answer where it is trusted (outside every
// face's band), else OpenCASCADE's classifiers, one pool per solid.
#include "domain/brep/BrepSolidImpl.h"

#include <Standard_Failure.hxx>

#include "Error.h"
#include "domain/OpenCascadeWork.h"
#include "domain/brep/OcctConversions.h"

namespace oraclemesh {

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

bool BrepSolid::insideExact(const Point3& p) const {
  if (!impl_->box.contains(p, impl_->classifyTolerance)) return false;
  const OpenCascadeWork working(impl_->name);
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

}  // namespace oraclemesh
