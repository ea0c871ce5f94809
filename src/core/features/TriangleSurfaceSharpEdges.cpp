#include "features/TriangleSurfaceSharpEdges.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace oraclemesh {
namespace {

constexpr double kPi = 3.14159265358979323846;
// An edge split into more pieces than this is split into this many (sizes are checked
// against the model before features are made; this only bounds a pathological request).
constexpr int64_t kMaxPiecesPerEdge = 100000;

// Sharp-edge neighbours of every surface vertex, each list ascending.
std::vector<std::vector<int64_t>> sharpNeighbours(const std::vector<Point3>& points,
                                                   const std::vector<std::array<int64_t, 3>>& triangles,
                                                   double cosSharp) {
  std::vector<Point3> normals;
  normals.reserve(triangles.size());
  for (const auto& t : triangles) normals.push_back(unit(cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]])));
  std::map<std::pair<int64_t, int64_t>, std::vector<size_t>> trianglesOfEdge;
  for (size_t i = 0; i < triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int64_t a = triangles[i][k], b = triangles[i][(k + 1) % 3];
      trianglesOfEdge[std::minmax(a, b)].push_back(i);
    }
  std::vector<std::vector<int64_t>> neighbours(points.size());
  for (const auto& [edge, at] : trianglesOfEdge) {
    if (at.size() != 2) continue;
    const Point3 &n0 = normals[at[0]], &n1 = normals[at[1]];
    // A degenerate triangle has no normal to compare: its edges say nothing.
    if (norm(n0) == 0 || norm(n1) == 0 || dot(n0, n1) >= cosSharp) continue;
    neighbours[edge.first].push_back(edge.second);
    neighbours[edge.second].push_back(edge.first);
  }
  for (auto& list : neighbours) std::sort(list.begin(), list.end());
  return neighbours;
}

// Splits each segment longer than the local edge size evenly.
std::vector<Point3> splitLongSegments(const std::vector<Point3>& line, double maxSegmentLength,
                                      const std::function<double(const Point3&)>& localSegmentLength) {
  std::vector<Point3> out{line.front()};
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    const Point3 &p = line[i], &q = line[i + 1];
    double limit = maxSegmentLength;
    if (localSegmentLength) limit = std::min(limit, localSegmentLength(0.5 * (p + q)));
    int64_t pieces = 1;
    if (limit > 0 && std::isfinite(limit))
      pieces = std::clamp<int64_t>(static_cast<int64_t>(std::ceil(distance(p, q) / limit)), 1, kMaxPiecesPerEdge);
    for (int64_t k = 1; k < pieces; ++k) out.push_back(p + (static_cast<double>(k) / pieces) * (q - p));
    out.push_back(q);
  }
  return out;
}

}  // namespace

FeatureGraph extractTriangleSurfaceSharpEdges(const TriangleSurface& surface, int sourceIndex, double sharpAngleDeg,
                                              double maxSegmentLength,
                                              const std::function<double(const Point3&)>& localSegmentLength) {
  std::vector<Point3> points;
  std::vector<std::array<int64_t, 3>> triangles;
  surface.outwardTriangles(points, triangles);
  const double cosSharp = std::cos(sharpAngleDeg * kPi / 180);
  const std::vector<std::vector<int64_t>> neighbours = sharpNeighbours(points, triangles, cosSharp);

  const int64_t n = static_cast<int64_t>(points.size());
  std::vector<char> corner(n, 0);
  for (int64_t v = 0; v < n; ++v) {
    const auto& w = neighbours[v];
    if (w.empty()) continue;
    if (w.size() != 2) {
      corner[v] = 1;
      continue;
    }
    // A line that turns sharply here meets itself at an input angle (a hairpin at a thin
    // slot's end turns by 178 degrees in part.step's tessellation): the vertex is a corner,
    // so that the angle is seen (InputAngles) and the engines protect it.
    const Point3 in = unit(points[v] - points[w[0]]), out = unit(points[w[1]] - points[v]);
    corner[v] = dot(in, out) < cosSharp;
  }

  std::set<std::pair<int64_t, int64_t>> walked;
  auto walk = [&](int64_t from, int64_t to) {
    std::vector<int64_t> line{from};
    int64_t previous = from, current = to;
    walked.insert(std::minmax(previous, current));
    while (current != from && !corner[current]) {
      line.push_back(current);
      const auto& w = neighbours[current];
      const int64_t next = w[0] == previous ? w[1] : w[0];
      previous = current;
      current = next;
      walked.insert(std::minmax(previous, current));
    }
    line.push_back(current);
    return line;
  };

  std::vector<std::vector<int64_t>> lines;
  for (int64_t v = 0; v < n; ++v)
    if (corner[v])
      for (int64_t w : neighbours[v])
        if (!walked.count(std::minmax(v, w))) lines.push_back(walk(v, w));
  // What is left are closed lines with no corner.
  for (int64_t v = 0; v < n; ++v)
    for (int64_t w : neighbours[v])
      if (!walked.count(std::minmax(v, w))) lines.push_back(walk(v, w));

  FeatureGraph graph;
  int curve = 0;
  for (const auto& line : lines) {
    std::vector<Point3> at;
    at.reserve(line.size());
    for (int64_t v : line) at.push_back(points[v]);
    FeaturePolyline polyline;
    polyline.points = splitLongSegments(at, maxSegmentLength, localSegmentLength);
    polyline.curve = curve++;
    polyline.source = sourceIndex;
    graph.polylines.push_back(std::move(polyline));
  }
  return graph;
}

}  // namespace oraclemesh
