#pragma once
// Junction curves (src/README.md, "Features"): where the boundaries of two inputs cross, the
// composite boundary has a crease that belongs to neither input's B-rep edges (the circle
// where a pin leaves a plate's face, the lines where a cut box cuts a plate's faces). They
// are the OpenCASCADE sections between the faces of two inputs, kept only where they are a
// crease of the composite boundary, and made into constrained segments like sharp edges.
#include <memory>
#include <utility>
#include <vector>

#include "RunControl.h"
#include "domain/HierarchicalOracle.h"
#include "domain/Source.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

class JunctionCurves {
 public:
  // Sections between the boundaries of every two B-rep entries (material or cut) of `oracle`
  // whose bounding boxes overlap, and the parts of them that are creases of the composite
  // boundary. A point p of a section edge is kept when a small ring around p (radius 1e-4 of
  // the diagonal, in the plane normal to the curve) sees at least three label changes, or two
  // that do not make a flat surface: the two half-surfaces meet at an angle farther than
  // `creaseAngleDeg` from 180 degrees. Ends of kept parts are put on the surface that ends
  // them (a third entry's), found by bisection and secant along the exact curve.
  // Left out: section edges that are not between two faces (an edge of one input lying on the
  // other's surface: it is that input's own edge, a sharp-edge feature if sharp) and section
  // edges along which the two faces are tangent or coplanar (shared faces of touching boxes:
  // not a crease, or a crease carried by an input edge).
  static JunctionCurves compute(const HierarchicalOracle& oracle, double creaseAngleDeg = 30,
                                const RunControl* control = nullptr);

  JunctionCurves();
  ~JunctionCurves();
  JunctionCurves(JunctionCurves&&) noexcept;
  JunctionCurves& operator=(JunctionCurves&&) noexcept;

  // Number of junctions: section edges with at least one kept part.
  size_t size() const;
  // The two oracle entries (higher priority first) whose faces cross along junction i, and
  // their 0-based face indices (BrepTopology::face order).
  std::pair<int, int> entries(int junction) const;
  std::pair<int, int> faces(int junction) const;
  // The kept parts as polylines: exact ends (section vertices where the part reaches the end
  // of its section edge, so junctions sharing a vertex share the point bitwise), points on the
  // exact curve, segments no longer than maxSegmentLength and a small chord sagitta. A closed
  // curve kept whole is a closed polyline (front == back). `junction` is set, `source` and
  // `edge` are -1; curve ids are 0, 1, ... in output order. sagittaTolerance > 0 replaces
  // featureSagittaTolerance (CurveSampling.h) as the chord bound.
  FeatureGraph polylines(double maxSegmentLength, double sagittaTolerance = 0) const;
  // Nearest point of junction i's section edge to p.
  BoundaryProjection projectOnCurve(int junction, const Point3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Sharp-edge polylines (already clipped to the composite boundary) and junction polylines
// in one graph in which polylines meet only at bitwise-equal end points: wherever a junction
// polyline touches or crosses another polyline (a junction ending on a plate edge, two
// junctions meeting at a triple point), both are split at one shared point on their exact
// curves (an existing sharp-edge end or B-rep vertex when there is one within 1e-6 of the
// diagonal). Not where a junction runs along another curve (both exact curves a quarter
// segment away on either side): removeCoincidentFeatures keeps one copy there. Curve ids are renumbered 0, 1, ... in output order; source/edge/junction kept.
FeatureGraph joinJunctions(const FeatureGraph& sharp, const FeatureGraph& junctionPolylines,
                           const HierarchicalOracle& oracle, const JunctionCurves& junctions);

}  // namespace oraclemesh
