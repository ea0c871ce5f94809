#pragma once
// One input domain of the hierarchical oracle (thesis §2.3): it knows which points are
// inside it and where its boundary is. The oracle composes several of them by priority.
#include <memory>
#include <string>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

class BrepTopology;  // domain/BrepTopology.h

// The nearest boundary point of a source and the boundary patch it lies on
// (B-rep face index, 0-based in TopExp::MapShapes order; 0 for a sphere).
struct BoundaryProjection {
  Point3 point{};
  int patch = -1;
  double distance = std::numeric_limits<double>::infinity();
};

// A point on the boundary with its outward unit normal. Samples seed the mesher with
// points on every connected boundary component (Mesh_3's own seeding misses some).
struct BoundarySample {
  Point3 point{};
  Point3 normal{};
  int patch = -1;
};

// One place where a segment a->b crosses a source's boundary.
struct BoundaryCrossing {
  double t = 0.0;         // the point is a + t (b - a), t in [0, 1]
  Point3 point{};
  int patch = -1;         // boundary patch hit (B-rep face index; image: label on the far side)
  bool entering = false;  // the segment goes from outside to inside the source here
};

class Source {
 public:
  virtual ~Source() = default;

  // The input's name as the user gave it; used in every message about this input.
  virtual const std::string& name() const = 0;
  virtual Bbox bbox() const = 0;
  // Closed-set membership is not promised: points within the model tolerance of the
  // boundary may go either way. Must be const and thread-safe.
  virtual bool inside(const Point3& p) const = 0;
  virtual BoundaryProjection project(const Point3& p) const = 0;
  // The nearest point to p of boundary patch `patch` (for a B-rep, of that face, even where
  // another face is nearer). Sources whose patches are no smooth pieces (triangles, image
  // labels) answer with project(p).
  virtual BoundaryProjection projectOnPatch(const Point3& p, int patch) const {
    (void)patch;
    return project(p);
  }
  // At least one sample on every face / connected boundary component, about `spacing` apart.
  virtual std::vector<BoundarySample> boundarySamples(double spacing) const = 0;
  // Boundary crossings of the segment a->b, sorted by t. Sources with an exact intersection
  // override this; the default finds sign changes of inside() on `samples` steps and
  // bisects each to `tolerance` (absolute), with the patch from project().
  virtual std::vector<BoundaryCrossing> crossings(const Point3& a, const Point3& b) const;
  // Volume of the source on its own (used for reports and absurd-size checks).
  virtual double volume() const = 0;
  // The B-rep faces and edges behind this source, for the layers that follow them (sharp
  // edges, junctions, input angles, planar faces); nullptr for a source that is no B-rep.
  virtual const BrepTopology* brepTopology() const { return nullptr; }
};

// The bisection fallback behind Source::crossings, usable by overrides for segments their
// exact method cannot answer. Misses pairs of crossings closer than one step.
std::vector<BoundaryCrossing> crossingsByBisection(const Source& source, const Point3& a,
                                                  const Point3& b, int samples, double tolerance);

using SourcePtr = std::shared_ptr<const Source>;

}  // namespace oraclemesh
