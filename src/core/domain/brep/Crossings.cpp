// The exact crossings of a segment, face by face: closed form, Newton iteration, else
// OpenCASCADE's intersector; then sorted, with crossings through shared edges kept once and
// contradicting pairs settled by the classifier.
#include "domain/brep/BrepSolidImpl.h"

#include <Standard_Failure.hxx>
#include <gp_Lin.hxx>

#include <algorithm>

#include "Error.h"
#include "domain/OpenCascadeWork.h"
#include "domain/brep/OcctConversions.h"

namespace oraclemesh {

std::unique_ptr<BrepSolid::Impl::FaceIntersectors> BrepSolid::Impl::leaseIntersectors() const {
  {
    std::lock_guard<std::mutex> lock(intersectorMutex);
    if (!idleIntersectors.empty()) {
      std::unique_ptr<FaceIntersectors> lease = std::move(idleIntersectors.back());
      idleIntersectors.pop_back();
      return lease;
    }
  }
  auto lease = std::make_unique<FaceIntersectors>();
  lease->byFace.resize(faces.size());
  lease->domainByFace.resize(faces.size());
  lease->projectorByFace.resize(faces.size());
  return lease;
}

void BrepSolid::Impl::giveBack(std::unique_ptr<FaceIntersectors> lease) const {
  std::lock_guard<std::mutex> lock(intersectorMutex);
  idleIntersectors.push_back(std::move(lease));
}

std::vector<BoundaryCrossing> BrepSolid::Impl::exactCrossings(const Point3& a, const Point3& b,
                                                              const std::vector<FaceSpan>& candidates) const {
  std::vector<BoundaryCrossing> result;
  if (candidates.empty()) return result;
  const Point3 d = b - a;
  const double length = norm(d);
  const gp_Lin line(toGp(a), gp_Dir(d[0], d[1], d[2]));

  std::unique_ptr<FaceIntersectors> lease = leaseIntersectors();
  struct Hit {
    BoundaryCrossing crossing;
    int solid;
  };
  std::vector<Hit> hits;
  // A crossing of face f at w (along the line) and (u, v); its sense from the face's normal.
  auto addHit = [&](int f, double w, double u, double v) {
    gp_Pnt onSurface;
    gp_Vec du, dv;
    faceSurface[f]->D1(u, v, onSurface, du, dv);
    gp_Vec normal = du.Crossed(dv);
    if (faces[f].Orientation() == TopAbs_REVERSED) normal.Reverse();
    const double side = normal.X() * d[0] + normal.Y() * d[1] + normal.Z() * d[2];
    Hit hit;
    hit.crossing.t = w / length;
    hit.crossing.point = a + hit.crossing.t * d;
    hit.crossing.patch = f;
    hit.solid = solidOfFace[f];
    if (normal.Magnitude() <= 1e-12 * du.Magnitude() * dv.Magnitude()) {
      // A pole or an apex: no normal, so the side is read off the classifier just beyond.
      const double step = std::min(1.0 - hit.crossing.t, 1e-7 * diagonal / length);
      hit.crossing.entering = step > 0 && classifyExact(a + (hit.crossing.t + step) * d);
    } else if (side == 0.0) {
      return;
    } else {
      hit.crossing.entering = side < 0;
    }
    hits.push_back(hit);
  };
  std::vector<std::pair<double, gp_Pnt2d>> newtonHits;
  std::vector<LineHit> analyticHits;
  std::vector<size_t> nearSolution;
  for (const FaceSpan& span : candidates) {
    const int f = span.face;
    if (span.newtonOnly && analytic[f].kind != AnalyticSurface::Kind::None) {
      std::vector<LineHit>& found = analyticHits;
      found.clear();
      if (analyticCrossings(a, d, length, f, found, nearSolution, *lease)) {
        for (const LineHit& hit : found) addHit(f, hit.w, hit.u, hit.v);
        continue;
      }
    }
    // Each crossing of the face lies on the surface over one of the triangles near the
    // segment. When each of those is either certified beside the segment or steep enough for
    // one crossing over it, one Newton solve per steep triangle finds them all, and
    // OpenCASCADE's intersector is not needed (no seed at all: the face is not crossed).
    bool solved = span.newtonOnly && analytic[f].kind == AnalyticSurface::Kind::None;
    newtonHits.clear();
    const gp_XYZ direction(d[0], d[1], d[2]);
    for (size_t i = 0; solved && i < span.seeds.size(); ++i) {
      double t;
      gp_Pnt2d uv;
      NewtonResult found = newtonCrossing(a, d, length, f, span.seeds[i], t, uv);
      bool onSeedTriangle = found == NewtonResult::Crossing;
      if (found == NewtonResult::OffTriangle) {
        // A crossing of the line over another steep triangle near the segment: that is the
        // crossing near this seed (the surface cannot fold back between two patches the
        // line crosses steeply), and the seed's own triangle has none.
        found = NewtonResult::Unsure;
        const gp_Pnt point = toGp(a + t * d);
        for (size_t id : span.near) {
          double u = uv.X(), v = uv.Y();
          if (!steep(newtonTriangle[id], direction) || domainByTriangles(point, f, u, v, &id, 1) != Domain::In)
            continue;
          found = t < 0 || t > 1 ? NewtonResult::None : NewtonResult::Crossing;
          break;
        }
      }
      solved = found != NewtonResult::Unsure;
      if (found != NewtonResult::Crossing) continue;
      // The solution lies on a parametric triangle of the face: in the face's domain unless
      // a boundary chord is near. There OpenCASCADE's classification decides: outside, no
      // crossing; on the boundary (within the tolerance) the crossing may belong to the
      // neighbour face, which OpenCASCADE's intersector sorts out.
      double u = uv.X(), v = uv.Y();
      if (!(onSeedTriangle && newtonTriangle[span.seeds[i].triangle].interior) &&
          domainByTriangles(toGp(a + t * d), f, u, v, span.near.data(), span.near.size()) != Domain::In)
        solved = domainOf(*lease, f).Perform(uv) == TopAbs_IN;
      // Two seeds on a shared triangle edge find the same crossing: keep it once.
      if (solved && std::none_of(newtonHits.begin(), newtonHits.end(), [&](const auto& hit) {
            return std::abs(hit.first - t) * length <= 1e-9 * diagonal;
          }))
        newtonHits.emplace_back(t, uv);
    }
    if (solved) {
      for (const auto& [t, uv] : newtonHits) addHit(f, t * length, uv.X(), uv.Y());
      continue;
    }
    auto& intersector = lease->byFace[f];
    if (!intersector) intersector = std::make_unique<IntCurvesFace_Intersector>(faces[f], classifyTolerance);
    intersector->Perform(line, span.t0 * length, span.t1 * length);
    if (!intersector->IsDone()) continue;
    for (int i = 1; i <= intersector->NbPnt(); ++i) {
      if (intersector->Transition(i) == IntCurveSurface_Tangent) continue;
      const double w = intersector->WParameter(i);
      if (w < 0.0 || w > length) continue;
      addHit(f, w, intersector->UParameter(i), intersector->VParameter(i));
    }
  }
  giveBack(std::move(lease));

  std::sort(hits.begin(), hits.end(), [](const Hit& x, const Hit& y) {
    return x.crossing.t != y.crossing.t ? x.crossing.t < y.crossing.t : x.crossing.patch < y.crossing.patch;
  });
  // Along one solid the segment enters and leaves in turn. Two hits in a row in the same
  // sense are one crossing through the edge two faces share (or a seam) when they are at the
  // same place: keep the first. Farther apart, one of them is wrong (OpenCASCADE misses a
  // crossing or finds a spurious one on grazing B-spline faces, BRepIntCurveSurface_Inter
  // alike): the classifier between them says which one agrees with inside().
  const double sameEdge = 1e-6 * diagonal / length;
  std::vector<int> lastOfSolid(solids.size(), -1);  // index into `kept`
  std::vector<const Hit*> kept;
  for (const Hit& hit : hits) {
    int& last = lastOfSolid[hit.solid];
    if (last >= 0 && kept[last]->crossing.entering == hit.crossing.entering) {
      const Hit& previous = *kept[last];
      if (hit.crossing.t - previous.crossing.t <= sameEdge) continue;
      const bool insideBetween = classifyExact(a + 0.5 * (previous.crossing.t + hit.crossing.t) * d);
      // Entering twice: inside between them means the second is wrong, else the first.
      // Leaving twice: inside between them means the first is wrong, else the second.
      if (insideBetween == hit.crossing.entering) continue;
      kept[last] = nullptr;
    }
    last = static_cast<int>(kept.size());
    kept.push_back(&hit);
  }
  for (const Hit* hit : kept)
    if (hit) result.push_back(hit->crossing);
  return result;
}

std::vector<BoundaryCrossing> BrepSolid::crossings(const Point3& a, const Point3& b) const {
  const Impl& m = *impl_;
  if (distance(a, b) == 0.0) return {};
  CGAL::Bbox_3 box(m.box.min[0], m.box.min[1], m.box.min[2], m.box.max[0], m.box.max[1], m.box.max[2]);
  if (!SegmentBoxTest(a, b - a).meets(box, m.classifyTolerance)) return {};
  const OpenCascadeWork working(m.name);
  try {
    return m.exactCrossings(a, b, m.facesNearSegment(a, b));
  } catch (const Standard_Failure& failure) {
    throw Error("OpenCASCADE failed to intersect a segment with input '" + m.name + "' (" +
                failure.GetMessageString() + "): check the solid with Part > Check geometry");
  }
}

}  // namespace oraclemesh
