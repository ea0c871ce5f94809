// Labeled voxel images: the NRRD reader (encodings, types, geometry, every error a user can
// meet) and the image region source checked against an analytic ball.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "domain/LabeledImage.h"
#include "domain/NrrdReader.h"
#include "input_errors.h"

namespace oraclemesh {
namespace {

using test::inputErrorOf;

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "oraclemesh_labeled_image";
  std::filesystem::create_directories(dir);
  return dir / name;
}

void writeFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string gzipped(const std::string& data) {
  z_stream stream{};
  EXPECT_EQ(deflateInit2(&stream, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);  // +16: gzip wrapper
  std::string out(deflateBound(&stream, data.size()) + 32, '\0');
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  stream.avail_in = static_cast<uInt>(data.size());
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&stream, Z_FINISH), Z_STREAM_END);
  out.resize(stream.total_out);
  deflateEnd(&stream);
  return out;
}

// Samples of `bytes` bytes each, value i + 1 at position i (so every voxel is distinct).
std::string countingSamples(int count, int bytes, bool bigEndian) {
  std::string data;
  for (int i = 0; i < count; ++i)
    for (int b = 0; b < bytes; ++b) {
      const int shift = 8 * (bigEndian ? bytes - 1 - b : b);
      data.push_back(static_cast<char>(((i + 1) >> shift) & 0xff));
    }
  return data;
}

TEST(NrrdReader, RawUint8WithSpacings) {
  const auto path = scratch("raw.nrrd");
  writeFile(path, "NRRD0004\n# a comment\ntype: uchar\ndimension: 3\nsizes: 2 3 4\nspacings: 0.5 1 2\n"
                  "encoding: raw\nkey:=value\n\n" + countingSamples(24, 1, false));
  const auto image = readNrrdLabels(path.string(), "scan");
  EXPECT_EQ(image->size(), (std::array<int64_t, 3>{2, 3, 4}));
  EXPECT_EQ(image->spacing(), (Point3{0.5, 1, 2}));
  EXPECT_EQ(image->origin(), (Point3{0, 0, 0}));
  // NRRD's first axis is the fastest.
  EXPECT_EQ(image->at(1, 0, 0), 2);
  EXPECT_EQ(image->at(0, 1, 0), 3);
  EXPECT_EQ(image->at(1, 2, 3), 24);
  EXPECT_EQ(image->at(2, 0, 0), 0);  // outside the grid: background
}

TEST(NrrdReader, GzipBigEndianInt16WithSpaceDirectionsAndAFlippedAxis) {
  const auto path = scratch("gzip.nrrd");
  const std::string samples = countingSamples(24, 2, true);
  writeFile(path, "NRRD0005\ntype: short\ndimension: 3\nspace: left-posterior-superior\nsizes: 2 3 4\n"
                  "space directions: (-0.5,0,0) (0,1,0) (0,0,2)\nspace origin: (10,20,30)\nendian: big\n"
                  "encoding: gzip\n\n" + gzipped(samples));
  const auto image = readNrrdLabels(path.string(), "scan");
  EXPECT_EQ(image->spacing(), (Point3{0.5, 1, 2}));
  // Axis 0 runs towards -x: the file's first voxel (value 1) is at x = 10, the last one
  // along that axis (value 2) at x = 9.5, which becomes the stored index 0.
  EXPECT_EQ(image->origin(), (Point3{9.5, 20, 30}));
  EXPECT_EQ(image->at(1, 0, 0), 1);
  EXPECT_EQ(image->at(0, 0, 0), 2);
  EXPECT_EQ(image->at(0, 2, 3), 24);
}

TEST(NrrdReader, DetachedRawUint32AndAsciiInt32) {
  writeFile(scratch("detached.raw"), std::string(7, 'x') + countingSamples(8, 4, false));
  writeFile(scratch("detached.nhdr"), "NRRD0004\ntype: uint32\ndimension: 3\nsizes: 2 2 2\nendian: little\n"
                                      "encoding: raw\nbyte skip: -1\ndata file: detached.raw\n");
  const auto detached = readNrrdLabels(scratch("detached.nhdr").string(), "scan");
  EXPECT_EQ(detached->at(1, 1, 1), 8);
  EXPECT_EQ(detached->labelCounts().size(), 8u);

  writeFile(scratch("ascii.nrrd"), "NRRD0004\ntype: int32\ndimension: 3\nsizes: 2 1 1\nencoding: ascii\n\n-3 70000\n");
  const auto ascii = readNrrdLabels(scratch("ascii.nrrd").string(), "scan");
  EXPECT_EQ(ascii->at(0, 0, 0), -3);
  EXPECT_EQ(ascii->at(1, 0, 0), 70000);
}

TEST(NrrdReader, BadFilesNameTheFileAndTheFix) {
  const std::string header = "NRRD0004\ndimension: 3\nsizes: 2 2 2\n";
  struct Case {
    std::string name, content, problem, fix;
  };
  const std::vector<Case> cases = {
      {"text.nrrd", "hello\n", "NRRD magic", "give a NRRD label image"},
      {"float.nrrd", header + "type: float\nencoding: raw\nendian: little\n\n" + std::string(32, '\0'),
       "voxel type 'float' is not supported", "labels must be integers"},
      {"bzip.nrrd", header + "type: uchar\nencoding: bzip2\n\n", "encoding 'bzip2' is not supported",
       "encoding raw or gzip"},
      {"flat.nrrd", "NRRD0004\ndimension: 2\nsizes: 2 2\ntype: uchar\nencoding: raw\n\n1234", "dimension 2",
       "give a 3D label image"},
      {"short.nrrd", header + "type: uchar\nencoding: raw\n\n1234", "truncated: 4 bytes for 8 voxels",
       "export the image again"},
      {"shortgz.nrrd", header + "type: uchar\nencoding: gzip\n\n" + gzipped("1234").substr(0, 12),
       "truncated", "export the image again"},
      {"zero.nrrd", header + "type: uchar\nencoding: raw\nspacings: 1 0 1\n\n12345678", "axis 1 has spacing 0",
       "positive voxel sizes"},
      {"negative.nrrd", header + "type: uchar\nencoding: raw\nspacings: 1 1 -2\n\n12345678", "axis 2 has spacing -2",
       "positive voxel sizes"},
      {"oblique.nrrd", header + "type: uchar\nencoding: raw\nspace directions: (1,1,0) (0,1,0) (0,0,1)\n\n12345678",
       "rotated or sheared", "resample"},
      {"endian.nrrd", header + "type: ushort\nencoding: raw\n\n" + std::string(16, '\0'), "no 'endian' field",
       "endian: little"},
      {"lost.nhdr", header + "type: uchar\nencoding: raw\ndata file: lost.raw\n", "lost.raw' does not exist",
       "next to the header"},
      {"list.nhdr", header + "type: uchar\nencoding: raw\ndata file: LIST\n", "several files", "one file"},
      {"skip.nrrd", header + "type: uchar\nencoding: raw\nbyte skip: -5\n\n12345678", "'byte skip: -5' is not a valid count",
       "whole number of bytes"},
      {"lines.nrrd", header + "type: uchar\nencoding: raw\nline skip: \n\n12345678", "'line skip: ' is not a valid",
       "whole number of lines"},
  };
  for (const Case& c : cases) {
    const auto path = scratch(c.name);
    writeFile(path, c.content);
    const std::string message = inputErrorOf([&] { readNrrdLabels(path.string(), "scan"); });
    EXPECT_NE(message.find("input 'scan'"), std::string::npos) << c.name << ": " << message;
    EXPECT_NE(message.find(path.string()), std::string::npos) << c.name << ": " << message;
    EXPECT_NE(message.find(c.problem), std::string::npos) << c.name << ": " << message;
    EXPECT_NE(message.find(c.fix), std::string::npos) << c.name << ": " << message;
  }
  const std::string missing = inputErrorOf([] { readNrrdLabels("/nonexistent/labels.nrrd", "scan"); });
  EXPECT_NE(missing.find("cannot read the image file '/nonexistent/labels.nrrd'"), std::string::npos) << missing;
}

// A ball of radius 5 voxelized on an anisotropic grid, with a smaller ball of label 2 inside
// it (a cavity for label 1) and a separate cube of label 1 away from it.
struct BallImage {
  Point3 centre{3.1, 2.9, 4.2};
  double radius = 2.5;
  double innerRadius = 0.8;
  std::shared_ptr<const LabeledImage> image;

  BallImage() {
    const std::array<int64_t, 3> size{40, 36, 32};
    const Point3 spacing{0.16, 0.18, 0.3}, origin{0.0, 0.0, 0.0};
    std::vector<int32_t> labels(size[0] * size[1] * size[2], 0);
    for (int64_t k = 0, v = 0; k < size[2]; ++k)
      for (int64_t j = 0; j < size[1]; ++j)
        for (int64_t i = 0; i < size[0]; ++i, ++v) {
          const Point3 p{origin[0] + i * spacing[0], origin[1] + j * spacing[1], origin[2] + k * spacing[2]};
          const double r = distance(p, centre);
          if (r <= innerRadius) labels[v] = 2;
          else if (r <= radius) labels[v] = 1;
          else if (i >= 36 && j >= 32 && k >= 28) labels[v] = 1;  // the separate cube, 4 x 4 x 4 voxels
        }
    image = std::make_shared<const LabeledImage>(size, spacing, origin, std::move(labels), "test ball");
  }
  double maxSpacing() const { return 0.3; }
};

TEST(ImageLabelRegion, VolumeIsTheVoxelCountAndApproximatesTheBall) {
  BallImage ball;
  const auto regions = makeImageRegions(ball.image, {{1, 7}, {2, 3}}, "scan");
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_EQ(regions[0].second, 7);
  EXPECT_EQ(regions[0].first->name(), "scan label 1");
  const double voxel = 0.16 * 0.18 * 0.3;
  EXPECT_DOUBLE_EQ(regions[0].first->volume(), ball.image->labelCounts().at(1) * voxel);
  constexpr double kPi = 3.14159265358979323846;
  const double shell = 4.0 / 3.0 * kPi * (std::pow(ball.radius, 3) - std::pow(ball.innerRadius, 3));
  const double cube = 64 * voxel;
  EXPECT_NEAR(regions[0].first->volume(), shell + cube, 0.02 * shell);
  EXPECT_NEAR(regions[1].first->volume(), 4.0 / 3.0 * kPi * std::pow(ball.innerRadius, 3),
              0.06 * 4.0 / 3.0 * kPi * std::pow(ball.innerRadius, 3));
}

TEST(ImageLabelRegion, NonFinitePointsAreOutsideAndCrossNothing) {
  BallImage ball;
  const ImageLabelRegion outer(ball.image, 1, "scan label 1");
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Point3& p : {Point3{nan, 0, 0}, Point3{0, inf, 0}, Point3{-inf, nan, 1}}) {
    EXPECT_FALSE(outer.inside(p));
    EXPECT_EQ(outer.project(p).patch, -1);
    EXPECT_TRUE(outer.crossings(ball.centre, p).empty());
  }
  // A finite segment from the centre out through the shell still crosses it.
  EXPECT_FALSE(outer.crossings(ball.centre, ball.centre + Point3{3 * ball.radius, 0, 0}).empty());
}

TEST(ImageLabelRegion, InsideAndProjectAgreeWithTheBall) {
  BallImage ball;
  const ImageLabelRegion outer(ball.image, 1, "scan label 1");
  const ImageLabelRegion inner(ball.image, 2, "scan label 2");
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  int checked = 0;
  for (int n = 0; n < 4000; ++n) {
    const Point3 p = ball.centre + 3.0 * Point3{unit(random), unit(random), unit(random)};
    const double r = distance(p, ball.centre);
    if (p[0] > 5.5 && p[1] > 5.5) continue;  // near the separate cube
    // Farther than a voxel from both spheres: the image says what the balls say.
    if (std::abs(r - ball.radius) > ball.maxSpacing() && std::abs(r - ball.innerRadius) > ball.maxSpacing()) {
      EXPECT_EQ(outer.inside(p), r > ball.innerRadius && r < ball.radius) << r;
      EXPECT_EQ(inner.inside(p), r < ball.innerRadius) << r;
      EXPECT_FALSE(outer.inside(p) && inner.inside(p));
      ++checked;
    }
    // Near the outer sphere: the projection is on the region's boundary (field 0), about
    // where the ball's surface is, and `distance` is the distance moved.
    if (std::abs(r - ball.radius) < 0.5 * ball.maxSpacing()) {
      const BoundaryProjection q = outer.project(p);
      EXPECT_NEAR(ball.image->margin(1, q.point).value, 0, 1e-12);
      EXPECT_NEAR(q.distance, distance(p, q.point), 1e-12);
      EXPECT_NEAR(distance(q.point, ball.centre), ball.radius, ball.maxSpacing());
      EXPECT_LE(q.distance, std::abs(r - ball.radius) + ball.maxSpacing());
      EXPECT_EQ(q.patch, 0);  // background across the outer surface
      EXPECT_LT(outer.project(q.point).distance, 1e-9);  // a boundary point stays put
    }
  }
  EXPECT_GT(checked, 1000);
  // Far from the boundary (the centre of the cavity, where the field is flat) the outer
  // region's nearest boundary is the cavity wall, with label 2 across it; the inner region
  // sees label 1 across the same wall.
  const BoundaryProjection fromCentre = outer.project(ball.centre);
  EXPECT_NEAR(fromCentre.distance, ball.innerRadius, ball.maxSpacing());
  EXPECT_EQ(fromCentre.patch, 2);
  EXPECT_EQ(inner.project(ball.centre + Point3{0.7, 0, 0}).patch, 1);
}

TEST(ImageLabelRegion, CrossingsOfLinesThroughTheBall) {
  BallImage ball;
  const ImageLabelRegion inner(ball.image, 2, "scan label 2");
  const ImageLabelRegion outer(ball.image, 1, "scan label 1");
  std::mt19937 random(11);
  std::normal_distribution<double> gauss;
  for (int n = 0; n < 50; ++n) {
    Point3 d{gauss(random), gauss(random), gauss(random)};
    d = (1.0 / norm(d)) * d;
    const Point3 a = ball.centre - 2.0 * d, b = ball.centre + 2.0 * d;  // through the centre, ends inside label 1
    const auto crossings = inner.crossings(a, b);
    ASSERT_EQ(crossings.size(), 2u) << n;
    EXPECT_TRUE(crossings[0].entering);
    EXPECT_FALSE(crossings[1].entering);
    EXPECT_EQ(crossings[0].patch, 1);
    EXPECT_EQ(crossings[1].patch, 1);
    const double length = 4.0;
    EXPECT_NEAR(crossings[0].t * length, 2.0 - ball.innerRadius, ball.maxSpacing());
    EXPECT_NEAR(crossings[1].t * length, 2.0 + ball.innerRadius, ball.maxSpacing());
    for (const BoundaryCrossing& c : crossings) {
      EXPECT_NEAR(ball.image->margin(2, c.point).value, 0, 1e-8);
      // The region changes across the crossing: its own answer, not the ball's.
      EXPECT_NE(inner.inside(c.point - 1e-6 * d), inner.inside(c.point + 1e-6 * d));
    }
    // The outer region (label 1) is left and re-entered at the same two points, with the
    // inner label across.
    const auto outerCrossings = outer.crossings(a, b);
    ASSERT_EQ(outerCrossings.size(), 2u);
    EXPECT_FALSE(outerCrossings[0].entering);
    EXPECT_EQ(outerCrossings[0].patch, 2);
    EXPECT_NEAR(outerCrossings[0].t, crossings[0].t, 1e-9);
    // The generic bisection on inside() finds the same crossings.
    const auto reference = crossingsByBisection(inner, a, b, 400, 1e-12);
    ASSERT_EQ(reference.size(), 2u);
    EXPECT_NEAR(reference[0].t, crossings[0].t, 1e-8);
    EXPECT_NEAR(reference[1].t, crossings[1].t, 1e-8);
  }
  // A segment that misses the region has no crossing.
  EXPECT_TRUE(inner.crossings({0, 0, 0}, {0.5, 0.5, 0.5}).empty());
}

TEST(ImageLabelRegion, BoundarySamplesSeedEveryComponent) {
  BallImage ball;
  const ImageLabelRegion outer(ball.image, 1, "scan label 1");
  // Even with one sample per huge bucket, the outer sphere, the cavity wall and the separate
  // cube each get a sample.
  const auto samples = outer.boundarySamples(1e6);
  bool onOuter = false, onCavity = false, onCube = false;
  for (const BoundarySample& s : samples) {
    EXPECT_NEAR(ball.image->margin(1, s.point).value, 0, 1e-12);
    EXPECT_TRUE(outer.inside(s.point - 1e-6 * s.normal));
    EXPECT_FALSE(outer.inside(s.point + 1e-6 * s.normal));
    const double r = distance(s.point, ball.centre);
    onOuter |= std::abs(r - ball.radius) < ball.maxSpacing() && s.patch == 0;
    onCavity |= std::abs(r - ball.innerRadius) < ball.maxSpacing() && s.patch == 2;
    onCube |= s.point[0] > 5.5 && s.point[1] > 5.5;
  }
  EXPECT_TRUE(onOuter && onCavity && onCube) << samples.size();
  EXPECT_LE(samples.size(), 10u);
  // With a spacing of a voxel or two, the samples cover the sphere densely.
  EXPECT_GT(outer.boundarySamples(0.5).size(), 4 * 3.14 * 2.5 * 2.5 / (0.5 * 0.5) / 2);
}

TEST(ImageLabelRegion, MappedLabelsMustOccur) {
  BallImage ball;
  std::string message = inputErrorOf([&] { makeImageRegions(ball.image, {{1, 1}, {5, 2}}, "scan"); });
  EXPECT_NE(message.find("label 5 of the 'materials' map of input 'scan' does not occur in test ball"), std::string::npos) << message;
  EXPECT_NE(message.find("labels present: 1, 2"), std::string::npos) << message;
  message = inputErrorOf([&] { makeImageRegions(ball.image, {{4, 1}, {5, 2}}, "scan"); });
  EXPECT_NE(message.find("no voxel of test ball has a label of the 'materials' map (4, 5)"), std::string::npos)
      << message;
  message = inputErrorOf([] {
    LabeledImage({2, 2, 2}, {1, 0, 1}, {0, 0, 0}, std::vector<int32_t>(8, 1), "flat image");
  });
  EXPECT_NE(message.find("flat image has voxel spacing 0"), std::string::npos) << message;
}

}  // namespace
}  // namespace oraclemesh
