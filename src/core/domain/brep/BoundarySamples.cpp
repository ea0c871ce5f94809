// Seeds on every face: interior tessellation nodes and triangle centroids on the exact
// surface, about `spacing` apart, at least one per face.
#include "domain/brep/BrepSolidImpl.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Poly_Triangulation.hxx>
#include <TopLoc_Location.hxx>

#include <map>

#include "domain/OpenCascadeWork.h"
#include "domain/brep/OcctConversions.h"

namespace oraclemesh {

std::vector<BoundarySample> BrepSolid::boundarySamples(double spacing) const {
  const Impl& m = *impl_;
  const OpenCascadeWork working(m.name);
  // Candidates are face-interior points: interior tessellation nodes and the parametric
  // centroids of tessellation triangles, evaluated on the exact surface. Points on edges are
  // left out on purpose: the two faces of an edge would give near-duplicate seeds there, and
  // the edges are seeded by the features anyway.
  struct Candidate {
    gp_Pnt point;
    gp_Vec normal;
  };
  const bool thin = spacing > 0 && std::isfinite(spacing);
  const double cell = thin ? spacing : 1.0;
  auto cellOf = [&](const gp_Pnt& p) {
    return std::array<int64_t, 3>{static_cast<int64_t>(std::floor(p.X() / cell)),
                                  static_cast<int64_t>(std::floor(p.Y() / cell)),
                                  static_cast<int64_t>(std::floor(p.Z() / cell))};
  };
  std::map<std::array<int64_t, 3>, std::vector<Point3>> accepted;
  auto farFromAccepted = [&](const gp_Pnt& p) {
    if (!thin) return true;
    const auto c = cellOf(p);
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = accepted.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == accepted.end()) continue;
          for (const Point3& a : it->second)
            if (distance(a, toPoint3(p)) < 0.5 * spacing) return false;
        }
    return true;
  };

  std::vector<BoundarySample> samples;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const TopoDS_Face& face = m.faces[f];
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    BRepAdaptor_Surface surface(face, Standard_True);
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    std::vector<gp_Pnt2d> uvs;
    std::vector<gp_Vec> fallbackNormals;  // triangle normals where the surface normal degenerates
    if (!tri.IsNull() && tri->HasUVNodes()) {
      // Interior nodes are those not on any triangle edge that is used once (boundary).
      std::map<std::pair<int, int>, int> use;
      for (int t = 1; t <= tri->NbTriangles(); ++t) {
        int a, b, c;
        tri->Triangle(t).Get(a, b, c);
        for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) ++use[{std::min(u, v), std::max(u, v)}];
      }
      std::vector<char> onBoundary(tri->NbNodes() + 1, 0);
      for (const auto& [e, n] : use)
        if (n == 1) onBoundary[e.first] = onBoundary[e.second] = 1;
      const gp_Trsf trsf = loc.Transformation();
      for (int n = 1; n <= tri->NbNodes(); ++n)
        if (!onBoundary[n]) {
          uvs.push_back(tri->UVNode(n));
          fallbackNormals.emplace_back(0, 0, 0);
        }
      for (int t = 1; t <= tri->NbTriangles(); ++t) {
        int a, b, c;
        tri->Triangle(t).Get(a, b, c);
        const gp_Pnt2d ua = tri->UVNode(a), ub = tri->UVNode(b), uc = tri->UVNode(c);
        uvs.emplace_back((ua.X() + ub.X() + uc.X()) / 3, (ua.Y() + ub.Y() + uc.Y()) / 3);
        const gp_Pnt pa = tri->Node(a).Transformed(trsf), pb = tri->Node(b).Transformed(trsf),
                     pc = tri->Node(c).Transformed(trsf);
        gp_Vec n = gp_Vec(pa, pb).Crossed(gp_Vec(pa, pc));
        if (reversed) n.Reverse();
        fallbackNormals.push_back(n);
      }
    } else {
      // No tessellation for this face: its parametric middle, if that lies on the face.
      double u0, u1, v0, v1;
      BRepTools::UVBounds(face, u0, u1, v0, v1);
      uvs.emplace_back(0.5 * (u0 + u1), 0.5 * (v0 + v1));
      fallbackNormals.emplace_back(0, 0, 0);
    }

    std::vector<Candidate> candidates;
    for (size_t i = 0; i < uvs.size(); ++i) {
      gp_Pnt p;
      gp_Vec du, dv;
      surface.D1(uvs[i].X(), uvs[i].Y(), p, du, dv);
      gp_Vec n = du.Crossed(dv);
      if (reversed) n.Reverse();
      if (n.Magnitude() <= 1e-12 * std::max(du.Magnitude() * dv.Magnitude(), 1e-300)) n = fallbackNormals[i];
      if (n.Magnitude() <= 0) continue;
      candidates.push_back({p, n.Normalized()});
    }
    bool faceHasSample = false;
    for (const Candidate& c : candidates) {
      if (!farFromAccepted(c.point)) continue;
      samples.push_back({toPoint3(c.point), toPoint3(gp_Pnt(c.normal.XYZ())), static_cast<int>(f)});
      if (thin) accepted[cellOf(c.point)].push_back(toPoint3(c.point));
      faceHasSample = true;
    }
    if (!faceHasSample && !candidates.empty()) {
      // Every face gets a seed, even one smaller than the spacing: take its candidate farthest
      // from the seeds already placed, so it does not crowd them.
      size_t bestIndex = 0;
      double bestGap = -1;
      for (size_t i = 0; i < candidates.size(); ++i) {
        double gap = std::numeric_limits<double>::infinity();
        const auto cc = cellOf(candidates[i].point);
        for (int64_t dx = -1; dx <= 1; ++dx)
          for (int64_t dy = -1; dy <= 1; ++dy)
            for (int64_t dz = -1; dz <= 1; ++dz) {
              auto it = accepted.find({cc[0] + dx, cc[1] + dy, cc[2] + dz});
              if (it == accepted.end()) continue;
              for (const Point3& a : it->second) gap = std::min(gap, distance(a, toPoint3(candidates[i].point)));
            }
        if (gap > bestGap) {
          bestGap = gap;
          bestIndex = i;
        }
      }
      const Candidate& c = candidates[bestIndex];
      samples.push_back({toPoint3(c.point), toPoint3(gp_Pnt(c.normal.XYZ())), static_cast<int>(f)});
      if (thin) accepted[cellOf(c.point)].push_back(toPoint3(c.point));
    }
  }
  return samples;
}

}  // namespace oraclemesh
