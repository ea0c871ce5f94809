// The faces a segment may cross, from the box trees over the proxy triangles' grown boxes,
// with the Newton seeds of each face (or the verdict that only OpenCASCADE can answer it).
#include "domain/brep/BrepSolidImpl.h"

namespace oraclemesh {

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

}  // namespace oraclemesh
