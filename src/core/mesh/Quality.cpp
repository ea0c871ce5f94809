#include "mesh/Quality.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh/Topology.h"

namespace oraclemesh {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegreesPerRadian = 180.0 / kPi;

// Faces opposite corner 0, 1, 2, 3, each ordered so that its normal (v1-v0)x(v2-v0) points out
// of a positively oriented tet.
constexpr int kOutwardFaceOpposite[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

double determinant(const Point3& col0, const Point3& col1, const Point3& col2) { return dot(col0, cross(col1, col2)); }

}  // namespace

double tetVolume(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  return determinant(b - a, c - a, d - a) / 6.0;
}

std::array<double, 6> dihedralAngles(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  const std::array<Point3, 4> p{a, b, c, d};
  std::array<Point3, 4> outwardNormal;  // unnormalized, length = 2 x face area
  for (int k = 0; k < 4; ++k) {
    const auto& f = kOutwardFaceOpposite[k];
    outwardNormal[k] = cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]);
  }
  std::array<double, 6> angles{};
  for (int e = 0; e < 6; ++e) {
    const int i = kTetEdgeCorners[e][0], j = kTetEdgeCorners[e][1];
    // The two faces through edge ij are the ones opposite the other two corners.
    int others[2], n = 0;
    for (int k = 0; k < 4; ++k)
      if (k != i && k != j) others[n++] = k;
    const Point3& n1 = outwardNormal[others[0]];
    const Point3& n2 = outwardNormal[others[1]];
    // The interior angle is 180 degrees minus the angle between the outward normals. atan2
    // keeps full accuracy near 0 and 180 degrees, where acos of a dot product loses it.
    angles[e] = std::atan2(norm(cross(n1, n2)), -dot(n1, n2)) * kDegreesPerRadian;
  }
  return angles;
}

std::optional<Point3> circumcentreFromA(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  const Point3 u = b - a, v = c - a, w = d - a;
  const double det = determinant(u, v, w);
  if (det == 0) return std::nullopt;
  // The point equidistant from a, b, c, d solves 2 [u v w]^T x = (|u|^2, |v|^2, |w|^2), whose
  // solution by Cramer's rule is below.
  const Point3 centre = (1.0 / (2.0 * det)) * (dot(u, u) * cross(v, w) + dot(v, v) * cross(w, u) + dot(w, w) * cross(u, v));
  if (!std::isfinite(centre[0]) || !std::isfinite(centre[1]) || !std::isfinite(centre[2])) return std::nullopt;
  return centre;
}

double radiusEdgeRatio(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  double shortestSquared = std::numeric_limits<double>::infinity();
  const std::array<Point3, 4> p{a, b, c, d};
  for (const auto& e : kTetEdgeCorners) {
    const Point3 edge = p[e[1]] - p[e[0]];
    shortestSquared = std::min(shortestSquared, dot(edge, edge));
  }
  const std::optional<Point3> centre = circumcentreFromA(a, b, c, d);
  if (!centre || shortestSquared == 0) return std::numeric_limits<double>::infinity();
  const double ratio = norm(*centre) / std::sqrt(shortestSquared);
  return std::isfinite(ratio) ? ratio : std::numeric_limits<double>::infinity();
}

double tet10JacobianDeterminant(const Tet10Nodes& x, const std::array<double, 4>& l) {
  // Reference coordinates (xi, eta, zeta) = (l1, l2, l3), l0 = 1 - xi - eta - zeta, so the
  // gradient of l_i with respect to (xi, eta, zeta) is:
  static const Point3 gradL[4] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  // Shape functions: corner N_i = l_i (2 l_i - 1), mid node of edge ij N_ij = 4 l_i l_j.
  // J = sum over nodes of x_node (grad N_node)^T; its columns are dx/dxi, dx/deta, dx/dzeta.
  Point3 column[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  auto accumulate = [&](const Point3& node, const Point3& gradN) {
    for (int c = 0; c < 3; ++c) column[c] = column[c] + gradN[c] * node;
  };
  for (int i = 0; i < 4; ++i) accumulate(x[i], (4 * l[i] - 1) * gradL[i]);
  for (int e = 0; e < 6; ++e) {
    const int i = kTetEdgeCorners[e][0], j = kTetEdgeCorners[e][1];
    accumulate(x[4 + e], 4.0 * (l[i] * gradL[j] + l[j] * gradL[i]));
  }
  return determinant(column[0], column[1], column[2]);
}

double tet10MinJacobianAtCornersAndGaussPoints(const Tet10Nodes& nodes) {
  // The four-point rule: (a, b, b, b) and its permutations.
  constexpr double a = 0.5854101966249685, b = 0.1381966011250105;
  static const std::array<double, 4> samples[9] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1},
                                                   {0.25, 0.25, 0.25, 0.25}, {a, b, b, b}, {b, a, b, b},
                                                   {b, b, a, b}, {b, b, b, a}};
  double smallest = std::numeric_limits<double>::infinity();
  for (const auto& l : samples) smallest = std::min(smallest, tet10JacobianDeterminant(nodes, l));
  return smallest;
}

Tet10Nodes tet10Nodes(const TetMesh& mesh, size_t t) {
  Tet10Nodes nodes;
  const auto& corners = mesh.tets[t];
  for (int i = 0; i < 4; ++i) nodes[i] = mesh.points[corners[i]];
  for (int e = 0; e < 6; ++e)
    nodes[4 + e] = mesh.order() == 2
                       ? mesh.points[mesh.tet_mid_nodes[t][e]]
                       : 0.5 * (nodes[kTetEdgeCorners[e][0]] + nodes[kTetEdgeCorners[e][1]]);
  return nodes;
}

double elementVolume(const TetMesh& mesh, size_t t) {
  if (mesh.order() == 1) {
    const auto& v = mesh.tets[t];
    return tetVolume(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]);
  }
  // det J of a tet10 is a cubic polynomial; this five-point rule on the reference tet
  // (centroid with weight -4/5, four points (1/2, 1/6, 1/6, 1/6) with weight 9/20, weights
  // normalized to 1) integrates cubics exactly. The reference tet has volume 1/6.
  const Tet10Nodes nodes = tet10Nodes(mesh, t);
  double integral = -0.8 * tet10JacobianDeterminant(nodes, {0.25, 0.25, 0.25, 0.25});
  for (int k = 0; k < 4; ++k) {
    std::array<double, 4> l{1.0 / 6, 1.0 / 6, 1.0 / 6, 1.0 / 6};
    l[k] = 0.5;
    integral += 0.45 * tet10JacobianDeterminant(nodes, l);
  }
  return integral / 6.0;
}

QualityReport measureQuality(const TetMesh& mesh) {
  requireConsistentIndices(mesh);
  QualityReport report;
  if (mesh.tets.empty()) return report;
  report.min_dihedral = std::numeric_limits<double>::infinity();
  report.max_dihedral = -std::numeric_limits<double>::infinity();
  double radiusEdgeSum = 0;
  int64_t finiteRadiusEdgeCount = 0;
  const int bins = static_cast<int>(report.min_dihedral_histogram.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    const Point3 &a = mesh.points[v[0]], &b = mesh.points[v[1]], &c = mesh.points[v[2]], &d = mesh.points[v[3]];
    const std::array<double, 6> angles = dihedralAngles(a, b, c, d);
    double tetMin = angles[0], tetMax = angles[0];
    for (double angle : angles) {
      tetMin = std::min(tetMin, angle);
      tetMax = std::max(tetMax, angle);
    }
    report.min_dihedral = std::min(report.min_dihedral, tetMin);
    report.max_dihedral = std::max(report.max_dihedral, tetMax);
    report.min_dihedral_histogram[std::clamp(static_cast<int>(tetMin / 10.0), 0, bins - 1)]++;

    // A flat tet's ratio is infinite: it is the maximum, but it would drown the mean.
    const double ratio = radiusEdgeRatio(a, b, c, d);
    report.max_radius_edge = std::max(report.max_radius_edge, ratio);
    if (std::isfinite(ratio)) {
      radiusEdgeSum += ratio;
      ++finiteRadiusEdgeCount;
    }

    if (tetVolume(a, b, c, d) <= 0) ++report.inverted;
    const int material = mesh.tet_materials[t];
    report.tets_per_material[material]++;
    report.volume_per_material[material] += elementVolume(mesh, t);
  }
  report.mean_radius_edge = finiteRadiusEdgeCount ? radiusEdgeSum / finiteRadiusEdgeCount : 0;
  return report;
}

}  // namespace oraclemesh
