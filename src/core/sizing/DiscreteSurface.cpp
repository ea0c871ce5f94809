#include "sizing/DiscreteSurface.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "RunControl.h"
#include "domain/LabeledImage.h"
#include "domain/TriangleSurface.h"

namespace oraclemesh {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Taubin's smoothing (a shrinking step then an inflating one, so a ball keeps its radius)
// turns the voxel faces' staircase into a surface whose normals turn as the label's boundary
// does; with fewer pairs the steps of single voxels still show in the normals, and the
// curvature they read asks for sizes near one voxel everywhere.
constexpr int kSmoothingPairs = 100;
constexpr double kShrink = 0.5, kInflate = -0.53;
// The smoothed surface's normals still tilt by a few degrees from one voxel to the next; its
// curvature is measured over points this many edges away (sizing/DiscreteSurface.h).
constexpr int kCurvatureRings = 3;

void smooth(std::vector<Point3>& points, const std::vector<std::vector<int64_t>>& neighbours,
            const RunControl& control) {
  std::vector<Point3> next(points.size());
  for (int pass = 0; pass < 2 * kSmoothingPairs; ++pass) {
    control.checkpoint();
    const double weight = pass % 2 == 0 ? kShrink : kInflate;
    for (size_t p = 0; p < points.size(); ++p) {
      if (neighbours[p].empty()) {
        next[p] = points[p];
        continue;
      }
      Point3 mean{0, 0, 0};
      for (int64_t q : neighbours[p]) mean = mean + points[q];
      mean = (1.0 / static_cast<double>(neighbours[p].size())) * mean;
      next[p] = points[p] + weight * (mean - points[p]);
    }
    points.swap(next);
  }
}

// The voxel faces between `label` and any other label (background included), each as two
// triangles with its corners at voxel corners, outward; then smoothed.
DiscreteSurface imageLabelSurface(const LabeledImage& image, int32_t label, const RunControl& control) {
  DiscreteSurface surface;
  const Point3& s = image.spacing();
  const Point3& o = image.origin();
  const auto [lo, hi] = image.indexBox(label);
  // Corner (a, b, c) sits at origin + (a - 1/2, b - 1/2, c - 1/2) spacings; corner indices
  // run one past the voxel box on each side.
  const int64_t na = hi[0] - lo[0] + 2, nb = hi[1] - lo[1] + 2;
  std::unordered_map<int64_t, int64_t> pointOfCorner;
  std::vector<std::vector<int64_t>> neighbours;
  const auto corner = [&](int64_t a, int64_t b, int64_t c) {
    const int64_t key = (a - lo[0]) + na * ((b - lo[1]) + nb * (c - lo[2]));
    auto [it, fresh] = pointOfCorner.try_emplace(key, static_cast<int64_t>(surface.points.size()));
    if (fresh) {
      surface.points.push_back({o[0] + (a - 0.5) * s[0], o[1] + (b - 0.5) * s[1], o[2] + (c - 0.5) * s[2]});
      neighbours.emplace_back();
    }
    return it->second;
  };
  const auto link = [&](int64_t p, int64_t q) {
    if (std::find(neighbours[p].begin(), neighbours[p].end(), q) == neighbours[p].end()) {
      neighbours[p].push_back(q);
      neighbours[q].push_back(p);
    }
  };
  for (int64_t k = lo[2]; k <= hi[2]; ++k)
    for (int64_t j = lo[1]; j <= hi[1]; ++j)
      for (int64_t i = lo[0]; i <= hi[0]; ++i) {
        if (image.at(i, j, k) != label) continue;
        const int64_t voxel[3] = {i, j, k};
        for (int axis = 0; axis < 3; ++axis)
          for (int side : {-1, 1}) {
            int64_t across[3] = {i, j, k};
            across[axis] += side;
            if (image.at(across[0], across[1], across[2]) == label) continue;
            // The face's corners in the plane of the two other axes b, c (axis, b, c cyclic, so
            // e_b x e_c = e_axis): counter-clockwise about the outward normal.
            const int b = (axis + 1) % 3, c = (axis + 2) % 3;
            int64_t quad[4];
            const int64_t steps[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int q = 0; q < 4; ++q) {
              int64_t at[3] = {voxel[0], voxel[1], voxel[2]};
              at[axis] += side > 0 ? 1 : 0;
              at[b] += steps[q][0];
              at[c] += steps[q][1];
              quad[q] = corner(at[0], at[1], at[2]);
            }
            if (side < 0) std::swap(quad[1], quad[3]);
            for (int q = 0; q < 4; ++q) link(quad[q], quad[(q + 1) % 4]);
            surface.triangles.push_back({quad[0], quad[1], quad[2]});
            surface.triangles.push_back({quad[0], quad[2], quad[3]});
          }
      }
  smooth(surface.points, neighbours, control);
  // Smoothing moves the staircase's corners up to about half a voxel; the oracle's boundary
  // passes through the voxel faces' centres.
  surface.deviation = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  surface.resolution = std::min({s[0], s[1], s[2]});
  surface.curvature_rings = kCurvatureRings;
  return surface;
}

}  // namespace

bool hasDiscreteSurface(const Source& source) {
  return dynamic_cast<const TriangleSurface*>(&source) || dynamic_cast<const ImageLabelRegion*>(&source);
}

DiscreteSurface discreteSurfaceOf(const Source& source, const RunControl& control) {
  if (const auto* triangles = dynamic_cast<const TriangleSurface*>(&source)) {
    DiscreteSurface surface;
    triangles->outwardTriangles(surface.points, surface.triangles);
    return surface;
  }
  if (const auto* region = dynamic_cast<const ImageLabelRegion*>(&source))
    return imageLabelSurface(region->image(), region->label(), control);
  return {};
}

namespace {

// A smoothed surface (no sharp edges left, its points' normals noisy at the scale of one
// edge): the curvature from the same formula over the points within `rings` edges of each
// point, whose farther reach divides the normal's noise by as much.
std::vector<std::array<double, 3>> ringCurvatures(const DiscreteSurface& surface, int rings) {
  std::vector<Point3> normals(surface.points.size(), Point3{0, 0, 0});
  std::vector<std::vector<int64_t>> neighbours(surface.points.size());
  for (const auto& c : surface.triangles) {
    const Point3 area = cross(surface.points[c[1]] - surface.points[c[0]], surface.points[c[2]] - surface.points[c[0]]);
    for (int k = 0; k < 3; ++k) {
      normals[c[k]] = normals[c[k]] + area;
      auto& next = neighbours[c[k]];
      if (std::find(next.begin(), next.end(), c[(k + 1) % 3]) == next.end()) next.push_back(c[(k + 1) % 3]);
    }
  }
  std::vector<double> curvature(surface.points.size(), 0.0);
  std::vector<int> reachedFrom(surface.points.size(), -1);
  for (size_t p = 0; p < surface.points.size(); ++p) {
    const double length = norm(normals[p]);
    if (!(length > 0)) continue;
    const Point3 n = (1 / length) * normals[p];
    std::vector<int64_t> ring{static_cast<int64_t>(p)}, next;
    reachedFrom[p] = static_cast<int>(p);
    for (int r = 0; r < rings; ++r) {
      next.clear();
      for (int64_t q : ring)
        for (int64_t m : neighbours[q])
          if (reachedFrom[m] != static_cast<int>(p)) {
            reachedFrom[m] = static_cast<int>(p);
            next.push_back(m);
          }
      ring.swap(next);
    }
    // The outermost ring only: the nearer points' reach is too short for the noise. Its upper
    // quartile, not its largest: on a sphere the largest of noisy estimates is the noise's
    // upper tail; on a cylinder the upper quartile of the directions is within 15 % of the
    // tightest one.
    std::vector<double> estimates;
    for (int64_t q : ring) {
      const Point3 edge = surface.points[q] - surface.points[p];
      const double squared = dot(edge, edge);
      if (squared > 0) estimates.push_back(2 * std::abs(dot(n, edge)) / squared);
    }
    if (estimates.empty()) continue;
    const auto quartile = estimates.begin() + static_cast<std::ptrdiff_t>(3 * estimates.size() / 4);
    std::nth_element(estimates.begin(), quartile, estimates.end());
    curvature[p] = *quartile;
  }
  std::vector<std::array<double, 3>> out;
  out.reserve(surface.triangles.size());
  for (const auto& c : surface.triangles) out.push_back({curvature[c[0]], curvature[c[1]], curvature[c[2]]});
  return out;
}

}  // namespace

std::vector<std::array<double, 3>> cornerCurvatures(const DiscreteSurface& surface, double sharpAngleDeg) {
  if (surface.curvature_rings > 1) return ringCurvatures(surface, surface.curvature_rings);
  const size_t count = surface.triangles.size();
  std::vector<Point3> normals(count, Point3{0, 0, 0});  // unit; zero for a degenerate triangle
  std::vector<std::vector<std::pair<size_t, int>>> cornersAt(surface.points.size());  // triangle, corner
  for (size_t t = 0; t < count; ++t) {
    const auto& c = surface.triangles[t];
    const Point3& a = surface.points[c[0]];
    const Point3 n = cross(surface.points[c[1]] - a, surface.points[c[2]] - a);
    const double length = norm(n);
    if (length > 0) normals[t] = (1 / length) * n;
    for (int k = 0; k < 3; ++k) cornersAt[c[k]].push_back({t, k});
  }
  // A triangle's angle at its corner k: weighting the normals around a point by it makes the
  // point's normal independent of how the sheet is cut into triangles (Thuermer and Wuethrich).
  const auto angleAt = [&](size_t t, int k) {
    const auto& c = surface.triangles[t];
    const Point3& p = surface.points[c[k]];
    const Point3 u = surface.points[c[(k + 1) % 3]] - p, v = surface.points[c[(k + 2) % 3]] - p;
    return std::atan2(norm(cross(u, v)), dot(u, v));
  };
  const double cosSharp = std::cos(sharpAngleDeg * kPi / 180);
  std::vector<std::array<double, 3>> curvature(count, {0, 0, 0});
  for (size_t t = 0; t < count; ++t) {
    if (norm(normals[t]) == 0) continue;
    const auto& c = surface.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int64_t p = c[k];
      const auto onSheet = [&](size_t s) { return dot(normals[s], normals[t]) >= cosSharp; };
      Point3 sheet{0, 0, 0};
      for (const auto& [s, corner] : cornersAt[p])
        if (onSheet(s)) sheet = sheet + angleAt(s, corner) * normals[s];
      const double length = norm(sheet);
      if (!(length > 0)) continue;
      const Point3 n = (1 / length) * sheet;
      for (const auto& [s, corner] : cornersAt[p]) {
        if (!onSheet(s)) continue;
        for (int other : {1, 2}) {
          const Point3 edge = surface.points[surface.triangles[s][(corner + other) % 3]] - surface.points[p];
          const double squared = dot(edge, edge);
          if (squared > 0) curvature[t][k] = std::max(curvature[t][k], 2 * std::abs(dot(n, edge)) / squared);
        }
      }
    }
  }
  return curvature;
}

}  // namespace oraclemesh
