// The sizing field (issue 16 item 1): the graded field against a brute-force minimum, and the
// sizes B-rep geometry, triangle surfaces and voxel images ask for (curvature, short edges,
// wall thickness) against the dimensions of hand-made solids.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <gp_Ax2.hxx>

#include <algorithm>
#include <cmath>
#include <random>

#include "RunControl.h"
#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"
#include "domain/LabeledImage.h"
#include "domain/TriangleSurface.h"
#include "sizing/DiscreteSurface.h"
#include "sizing/GeometrySizes.h"
#include "sizing/SizeField.h"
#include "sizing/TriangleSpread.h"
#include "discrete_shapes.h"

namespace oraclemesh {
namespace {

TEST(SizeField, IsTheGradedMinimumOverItsSamplesCapped) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-50, 50), size(0.01, 30);
  std::vector<SizeSample> samples;
  for (int i = 0; i < 2000; ++i) samples.push_back({{coord(rng), coord(rng), coord(rng)}, size(rng)});
  const double grading = 0.3, cap = 20, floor = 0.05;
  const SizeField field(samples, grading, cap, floor);
  for (int q = 0; q < 300; ++q) {
    const Point3 p{coord(rng) * 1.5, coord(rng) * 1.5, coord(rng) * 1.5};
    double expected = cap;
    for (const SizeSample& s : samples) expected = std::min(expected, std::max(s.size, floor) + grading * distance(p, s.point));
    ASSERT_NEAR(field.at(p), expected, 1e-12 * cap) << "query " << q;
  }
  EXPECT_DOUBLE_EQ(field.smallestSize(), floor);  // sizes under the floor are raised to it
}

// Samples as the face sampling makes them: dense along a surface, each point several times
// (the corners of every triangle around it), sizes varying slowly. Thinning drops most of
// them and keeps the field between the exact one and (1 + tolerance) times it.
TEST(SizeField, ThinnedSamplesStayWithinTheirToleranceOfAllSamples) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> along(0, 100), jitter(-0.01, 0.01);
  std::vector<SizeSample> samples;
  for (int i = 0; i < 20000; ++i) {
    const double x = along(rng), y = along(rng);
    const double size = 0.2 + 0.02 * x + 0.5 * std::abs(std::sin(y / 7));
    for (int copy = 0; copy < 3; ++copy) samples.push_back({{x + jitter(rng), y, 0}, size});
  }
  const double grading = 0.3, cap = 10, tolerance = 0.1;
  const SizeField all(samples, grading, cap, 0), thinned(samples, grading, cap, 0, tolerance);
  EXPECT_EQ(thinned.samplesTaken(), samples.size());
  EXPECT_LT(thinned.sampleCount(), samples.size() / 4);  // the copies, and more
  std::uniform_real_distribution<double> coord(-20, 120);
  for (int q = 0; q < 2000; ++q) {
    const Point3 p{coord(rng), coord(rng), 0.2 * coord(rng)};
    const double exact = all.at(p), thin = thinned.at(p);
    ASSERT_GE(thin, exact * (1 - 1e-12)) << "query " << q;
    ASSERT_LE(thin, (1 + tolerance) * exact * (1 + 1e-12)) << "query " << q;
  }
}

TEST(SizeField, GrowsNoFasterThanItsGrading) {
  const SizeField field({{{0, 0, 0}, 0.1}, {{10, 0, 0}, 2}}, 0.3, 50, 0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-20, 30);
  for (int q = 0; q < 500; ++q) {
    const Point3 a{coord(rng), coord(rng), coord(rng)}, b{coord(rng), coord(rng), coord(rng)};
    ASSERT_LE(std::abs(field.at(a) - field.at(b)), 0.3 * distance(a, b) * (1 + 1e-12));
  }
  EXPECT_DOUBLE_EQ(field.at({0, 0, 0}), 0.1);
  EXPECT_DOUBLE_EQ(field.at({10, 0, 0}), 2);  // 0.1 + 0.3 * 10 = 3.1 from the other sample
}

// The largest distance from a point of the triangle to its nearest spread point, over 3000
// random points of the triangle.
double farthestFromSpread(const Point3 (&c)[3], const std::vector<std::array<double, 2>>& spread, std::mt19937& rng) {
  std::vector<Point3> points;
  for (const auto& w : spread) points.push_back(w[0] * c[0] + w[1] * c[1] + (1 - w[0] - w[1]) * c[2]);
  std::uniform_real_distribution<double> unit(0, 1);
  double farthest = 0;
  for (int q = 0; q < 3000; ++q) {
    double a = unit(rng), b = unit(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Point3 p = a * c[0] + b * c[1] + (1 - a - b) * c[2];
    double nearest = std::numeric_limits<double>::infinity();
    for (const Point3& s : points) nearest = std::min(nearest, distance(p, s));
    farthest = std::max(farthest, nearest);
  }
  return farthest;
}

// Every point of a triangle within spacing / sqrt(3) of a sample point, corners included, no
// point twice: on a well-shaped triangle, an obtuse one and needles along and across the axes.
TEST(TriangleSpread, EveryPointOfTheTriangleLiesNearASpreadPoint) {
  const double spacing = 1;
  const Point3 triangles[][3] = {{{0, 0, 0}, {10, 0, 0}, {5, 8.66, 0}},
                                 {{0, 0, 0}, {12, 0, 0}, {7, 1.5, 0.5}},
                                 {{0, 0, 0}, {60, 0.3, 0}, {0.2, 0.05, 0}},
                                 {{3, -2, 1}, {3.1, 40, 1}, {3.05, 19, 1.4}},
                                 {{0, 0, 0}, {200, 0, 0}, {120, 20, 0}},
                                 {{0, 0, 0}, {0.4, 0, 0}, {0, 0.3, 0}}};
  std::mt19937 rng(5);
  for (const auto& c : triangles) {
    const std::vector<std::array<double, 2>> spread = spreadOverTriangle(c, spacing);
    std::vector<std::array<double, 2>> sorted = spread;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "a point twice";
    for (const std::array<double, 2>& corner : {std::array<double, 2>{1, 0}, {0, 1}, {0, 0}})
      EXPECT_TRUE(std::binary_search(sorted.begin(), sorted.end(), corner)) << corner[0] << " " << corner[1];
    EXPECT_LE(farthestFromSpread(c, spread, rng), spacing / std::sqrt(3.0) * (1 + 1e-9)) << c[1][0] << " " << c[1][1];
  }
}

// A needle 100 spacings long and a twentieth of one wide gets points along its length: the even
// grid over its longest edge had 101 * 102 / 2 = 5151. A well-shaped triangle keeps that grid.
TEST(TriangleSpread, ANeedleGetsPointsAlongItsLengthAWellShapedTriangleTheEvenGrid) {
  const Point3 needle[3] = {{0, 0, 0}, {100, 0, 0}, {50, 0.05, 0}};
  const size_t onNeedle = spreadOverTriangle(needle, 1).size();
  EXPECT_GE(onNeedle, 100u);  // at most a spacing apart along it
  EXPECT_LE(onNeedle, 150u);
  // Twenty spacings high, it gets rows: about one point per 0.4 x 0.82 spacings^2 of its area.
  const Point3 wide[3] = {{0, 0, 0}, {200, 0, 0}, {120, 20, 0}};
  const size_t onWide = spreadOverTriangle(wide, 1).size();
  EXPECT_LE(onWide, static_cast<size_t>(1.3 * 2000 / (0.4 * 0.82)));
  EXPECT_LT(onWide, 201u * 202 / 2 / 2);
  const Point3 equilateral[3] = {{0, 0, 0}, {10, 0, 0}, {5, 5 * std::sqrt(3.0), 0}};
  const std::vector<std::array<double, 2>> grid = spreadOverTriangle(equilateral, 1);
  ASSERT_EQ(grid.size(), 11u * 12 / 2);
  size_t k = 0;
  for (int a = 0; a <= 10; ++a)
    for (int b = 0; a + b <= 10; ++b, ++k) {
      EXPECT_EQ(grid[k][0], a / 10.0);
      EXPECT_EQ(grid[k][1], b / 10.0);
    }
  // The budget holds on a triangle far larger than the spacing.
  EXPECT_LE(spreadOverTriangle(equilateral, 1e-4, 5000).size(), 5000u);
}

std::vector<SizeSample> samplesOf(const TopoDS_Shape& shape, double sharpAngle = 30) {
  const HierarchicalOracle oracle({{std::make_shared<BrepSolid>(shape, "solid"), Role::Material, 1}});
  const FinenessPreset* moderate = findFineness("moderate");
  return geometrySizes(oracle, moderate, moderate->sizes_per_thickness, sharpAngle, 1e9, 1e-6 * oracle.diagonal(),
                       1e18, RunControl())
      .samples;
}

double smallest(const std::vector<SizeSample>& samples, SizeReason reason) {
  double s = std::numeric_limits<double>::infinity();
  for (const SizeSample& sample : samples)
    if (sample.reason == reason) s = std::min(s, sample.size);
  return s;
}

double largest(const std::vector<SizeSample>& samples, SizeReason reason) {
  double s = 0;
  for (const SizeSample& sample : samples)
    if (sample.reason == reason) s = std::max(s, sample.size);
  return s;
}

// 12 segments around ("moderate"): chords of 2 R sin(15 deg), triangles of that edge have a
// circumradius of chord / sqrt(3).
TEST(GeometrySizes, CurvedFacesAskForTwelveSegmentsAroundTheirRadius) {
  const double radius = 5;
  const auto samples = samplesOf(BRepPrimAPI_MakeCylinder(gp_Ax2(), radius, 40).Shape());
  const double expected = 2 * radius * std::sin(M_PI / 12) / std::sqrt(3.0);
  EXPECT_NEAR(smallest(samples, SizeReason::Curvature), expected, 1e-6 * expected);
  EXPECT_NEAR(largest(samples, SizeReason::Curvature), expected, 1e-6 * expected);  // a cylinder: one radius
}

// Two sizes... three through a wall at "moderate": a 100 x 100 x 1 plate asks for 1/3 across
// its thickness, its 100 mm sides for no less than 1/3 of 100 (the ray across the plate).
TEST(GeometrySizes, ThinWallsAskForThreeSizesThroughTheirThickness) {
  const auto samples = samplesOf(BRepPrimAPI_MakeBox(100, 100, 1).Shape());
  EXPECT_NEAR(smallest(samples, SizeReason::Thickness), 1.0 / 3, 1e-6);
  EXPECT_NEAR(largest(samples, SizeReason::Thickness), 100.0 / 3, 1e-6);
  // The 1 mm edges are sharp and short: at most half their length, so two edge segments.
  EXPECT_NEAR(smallest(samples, SizeReason::ShortEdge), 0.5, 1e-9);
  EXPECT_EQ(smallest(samples, SizeReason::Curvature), std::numeric_limits<double>::infinity());  // planes only
}

// A wedge is no wall: a prism 5 long whose section is a triangle with a 45 degree apex (a
// thread's flanks, a chamfer). Rays from one flank reach the other ever nearer the apex, which
// asked for sizes down to the field's floor; the flanks' normals are 135 degrees apart, not
// facing, so only the end caps, 5 apart, are a wall.
TEST(GeometrySizes, WedgesAreNoWalls) {
  const double height = 20, halfBase = height * std::tan(M_PI / 8);
  BRepBuilderAPI_MakePolygon section(gp_Pnt(-halfBase, 0, 0), gp_Pnt(halfBase, 0, 0), gp_Pnt(0, height, 0), true);
  const TopoDS_Shape prism = BRepPrimAPI_MakePrism(BRepBuilderAPI_MakeFace(section.Wire()).Face(), gp_Vec(0, 0, 5)).Shape();
  EXPECT_NEAR(smallest(samplesOf(prism), SizeReason::Thickness), 5.0 / 3, 1e-6);
}

// A cylinder's seam and the smooth edges are no mesh edges: only its two rims count as edges.
TEST(GeometrySizes, OnlySharpEdgesAskForSegments) {
  const auto samples = samplesOf(BRepPrimAPI_MakeCylinder(gp_Ax2(), 5, 40).Shape());
  const double rim = 2 * M_PI * 5;
  EXPECT_NEAR(smallest(samples, SizeReason::ShortEdge), rim / 2, 1e-6 * rim);  // not the 40 mm seam
  EXPECT_TRUE(std::isinf(smallest(samplesOf(BRepPrimAPI_MakeBox(10, 10, 1).Shape(), 0), SizeReason::ShortEdge)))
      << "sharp edges off: no edge sizes";
}

// Triangle surfaces and voxel images: the same sizes from their discrete surfaces.

std::vector<SizeSample> samplesOf(const SourcePtr& source, double sharpAngle = 30) {
  const HierarchicalOracle oracle({{source, Role::Material, 1}});
  const FinenessPreset* moderate = findFineness("moderate");
  return geometrySizes(oracle, moderate, moderate->sizes_per_thickness, sharpAngle, 1e9, 1e-6 * oracle.diagonal(),
                       1e18, RunControl())
      .samples;
}

SourcePtr surfaceOf(const test::Triangles& t, const std::string& name) {
  return TriangleSurface::fromTriangles(t.points, t.triangles, name);
}

TEST(DiscreteSizes, ATriangleSurfaceCylinderAsksForTwelveSegmentsAroundItsRadius) {
  const double radius = 5;
  const SourcePtr cylinder = surfaceOf(test::tessellatedCylinder({0, 0, 0}, radius, 40, 48), "cylinder");
  const auto samples = samplesOf(cylinder);
  const double expected = 2 * radius * std::sin(M_PI / 12) / std::sqrt(3.0);
  EXPECT_NEAR(smallest(samples, SizeReason::Curvature), expected, 0.01 * expected);
  EXPECT_NEAR(largest(samples, SizeReason::Curvature), expected, 0.01 * expected);
  // The rims are 90 degree edges: no curvature there. With sharp edges off (angle 0) the
  // default sharp angle still tells them from curves.
  EXPECT_NEAR(smallest(samplesOf(cylinder, 0), SizeReason::Curvature), expected, 0.01 * expected);
}

TEST(DiscreteSizes, ATriangleSurfacePlateAsksForThreeSizesThroughItsThickness) {
  const auto samples = samplesOf(surfaceOf(test::triangleBox({0, 0, 0}, 100, 100, 1), "plate"));
  EXPECT_NEAR(smallest(samples, SizeReason::Thickness), 1.0 / 3, 1e-6);
  EXPECT_NEAR(largest(samples, SizeReason::Thickness), 100.0 / 3, 1e-6);
  EXPECT_TRUE(std::isinf(smallest(samples, SizeReason::Curvature)));  // flat faces, sharp edges
}

// A ball of radius 12 voxels and a slab 3 voxels thick, labels 1 and 2 of one image: the ball's
// smoothed voxel faces ask for about what a sphere of its radius does, the slab for a third of
// its thickness.
TEST(DiscreteSizes, AVoxelBallAndSlabAskForTheirRadiusAndThickness) {
  const std::array<int64_t, 3> size{40, 40, 60};
  const double voxel = 0.5, radius = 12 * voxel;
  const Point3 centre{20 * voxel, 20 * voxel, 20 * voxel};
  std::vector<int32_t> labels(size[0] * size[1] * size[2], 0);
  for (int64_t k = 0, v = 0; k < size[2]; ++k)
    for (int64_t j = 0; j < size[1]; ++j)
      for (int64_t i = 0; i < size[0]; ++i, ++v) {
        if (distance(Point3{i * voxel, j * voxel, k * voxel}, centre) <= radius) labels[v] = 1;
        if (k >= 50 && k < 53 && i >= 5 && i < 35 && j >= 5 && j < 35) labels[v] = 2;
      }
  const auto image = std::make_shared<const LabeledImage>(size, Point3{voxel, voxel, voxel}, Point3{0, 0, 0},
                                                          std::move(labels), "test image");
  const auto ball = samplesOf(std::make_shared<ImageLabelRegion>(image, 1, "ball"));
  const double expected = 2 * radius * std::sin(M_PI / 12) / std::sqrt(3.0);
  std::vector<double> curvature;
  for (const SizeSample& s : ball)
    if (s.reason == SizeReason::Curvature) curvature.push_back(s.size);
  ASSERT_FALSE(curvature.empty());
  std::sort(curvature.begin(), curvature.end());
  const double median = curvature[curvature.size() / 2], low = curvature[curvature.size() / 10];
  std::cout << "[ figures  ] voxel ball: curvature sizes " << curvature.front() << " .. " << curvature.back()
            << ", 10th percentile " << low << ", median " << median << ", a sphere's " << expected << "\n";
  // Noise at the voxels' scale errs on the small side, within reason.
  EXPECT_GT(median, 0.7 * expected);
  EXPECT_LT(median, 1.1 * expected);
  EXPECT_GT(low, 0.5 * expected);
  EXPECT_GE(curvature.front(), voxel);  // the image resolves nothing finer
  EXPECT_TRUE(std::isinf(smallest(ball, SizeReason::Thickness)) || smallest(ball, SizeReason::Thickness) > radius / 2);

  const auto slab = samplesOf(std::make_shared<ImageLabelRegion>(image, 2, "slab"));
  EXPECT_NEAR(smallest(slab, SizeReason::Thickness), 3 * voxel / 3, 0.05 * voxel);
}

}  // namespace
}  // namespace oraclemesh
