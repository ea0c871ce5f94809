// Issue 18: bad bytes in the files a user gives are refused by the readers with a message
// naming the file, the defect and the fix, before anything large is allocated and before
// CGAL sees a coordinate; checks on user polylines come before they are sampled.
#include <gtest/gtest.h>
#include <zlib.h>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Pnt.hxx>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "domain/LabeledImage.h"
#include "domain/NrrdReader.h"
#include "domain/Sphere.h"
#include "domain/TriangleSurface.h"
#include "domain/BrepSolid.h"
#include "domain/brep/ShapeFiles.h"
#include "features/BrepSharpEdges.h"
#include "features/UserPolylines.h"
#include "input_errors.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

using test::inputErrorOf;
using namespace std::string_literals;

std::string scratch(const std::string& name, const std::string& bytes) {
  const auto dir = std::filesystem::temp_directory_path() / "oraclemesh_input_validation";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A binary STL of the unit tetrahedron whose vertex (0, 0, 0) is replaced by `first`.
std::string tetrahedronStl(float first) {
  const float p[4][3] = {{first, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int t[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string data(80, ' ');
  const uint32_t count = 4;
  data.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& tri : t) {
    const float normal[3] = {0, 0, 0};
    data.append(reinterpret_cast<const char*>(normal), 12);
    for (int v : tri) data.append(reinterpret_cast<const char*>(p[v]), 12);
    data.append(2, '\0');
  }
  return data;
}

TEST(InputValidation, NonFiniteStlVertexIsNamedAsSuch) {
  // Before: NaN reached CGAL as "encloses no volume", infinity as "intersects itself".
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    const std::string path = scratch("bad_vertex.stl", tetrahedronStl(bad));
    const std::string message = inputErrorOf([&] { TriangleSurface::fromFile(path, "bone"); });
    EXPECT_TRUE(contains(message, "input 'bone' (file '" + path + "') has a vertex with a coordinate that is not a "
                                  "finite number"))
        << message;
  }
  const std::string good = scratch("good.stl", tetrahedronStl(0));
  EXPECT_GT(TriangleSurface::fromFile(good, "bone")->volume(), 0.16);
}

TEST(InputValidation, OffCountsBeyondTheFileAreRefusedBeforeReading) {
  const std::string counts = scratch("counts.off", "OFF\n1000000000 1000000000 0\n0 0 0\n");
  EXPECT_TRUE(contains(inputErrorOf([&] { TriangleSurface::fromFile(counts, "part"); }),
                       "declares 1000000000 vertices and 1000000000 faces"));
  const std::string face = scratch("face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n");
  EXPECT_TRUE(contains(inputErrorOf([&] { TriangleSurface::fromFile(face, "part"); }),
                       "has a face with 2000000000 corners: only triangles are read"));
  const std::string binary = scratch("binary.off", std::string("OFF BINARY\n") + std::string(12, '\0'));
  EXPECT_TRUE(contains(inputErrorOf([&] { TriangleSurface::fromFile(binary, "part"); }), "binary OFF"));
  // Found by tests/fuzz: CGAL's scanner read colours past the end of a COFF vertex line.
  const std::string colours = scratch("colours.off", "COFF\n3 1 0\n0\0 0 0 255\n1 0 0\n0 1 0\n3 0 1 2\n"s);
  EXPECT_TRUE(contains(inputErrorOf([&] { TriangleSurface::fromFile(colours, "part"); }),
                       "has no x y z numbers at vertex 1 of 3 (line 3)"));
  const std::string good = scratch("good.off", "COFF\n# comment\n4 4 6\n0 0 0 1 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                               "3 0 2 1\n3 0 1 3\n3 0 3 2 255 0 0\n3 1 2 3\n");
  EXPECT_GT(TriangleSurface::fromFile(good, "part")->volume(), 0.16);
}

TEST(InputValidation, NrrdHeaderOfMissingDataAllocatesNothing) {
  // 1250^3 voxels declared over two bytes: refused as truncated, not after gigabytes.
  const std::string header = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1250 1250 1250\n";
  for (const std::string& data : {std::string("encoding: raw\n\n\x01\x02"), std::string("encoding: ascii\n\n1 2\n")}) {
    const std::string path = scratch("huge.nrrd", header + data);
    const auto start = std::chrono::steady_clock::now();
    const std::string message = inputErrorOf([&] { readNrrdLabels(path, "scan"); });
    EXPECT_TRUE(contains(message, "input 'scan'") && (contains(message, "truncated") || contains(message, "too few")))
        << message;
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
  }
  // gzip of 1000 zero bytes: inflated only as far as the data goes.
  std::string zeros(1000, '\0'), packed(2000, '\0');
  uLongf packedSize = packed.size();
  ASSERT_EQ(compress(reinterpret_cast<Bytef*>(packed.data()), &packedSize, reinterpret_cast<const Bytef*>(zeros.data()),
                     zeros.size()),
            Z_OK);
  packed.resize(packedSize);
  const std::string gz = scratch("huge_gz.nrrd", header + "encoding: gzip\n\n" + packed);
  EXPECT_TRUE(contains(inputErrorOf([&] { readNrrdLabels(gz, "scan"); }), "the data is truncated: 1000 bytes"));
}

TEST(InputValidation, NrrdNeedleVoxelsAreRefused) {
  // Spacings 1e-6 / 1 / 1e6 used to hang in the crossings' bisection (LabeledImage::margin).
  const std::string path = scratch("needles.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 3 3\n"
                                                   "spacings: 1e-6 1 1e6\nencoding: raw\n\n" +
                                                       std::string(13, '\0') + "\x01" + std::string(13, '\0'));
  const std::string message = inputErrorOf([&] { readNrrdLabels(path, "scan"); });
  EXPECT_TRUE(contains(message, "times longer along one axis than along another")) << message;
}

TEST(InputValidation, ImageCrossingsOfAFarSegmentEnd) {
  // The bisection stops where doubles cannot halve the interval any more: from 1e12 away
  // the tolerance (1e-9 of a voxel) is below the resolution of t.
  std::vector<int32_t> labels(27, 0);
  labels[13] = 1;
  const auto image = std::make_shared<const LabeledImage>(std::array<int64_t, 3>{3, 3, 3}, Point3{1, 1, 1},
                                                          Point3{0, 0, 0}, labels, "a test image");
  const ImageLabelRegion region(image, 1, "voxel");
  const auto crossings = region.crossings({-1e12, 1, 1}, {1, 1, 1});
  ASSERT_EQ(crossings.size(), 1u);
  EXPECT_NEAR(crossings[0].point[0], 0.5, 1e-3);
  EXPECT_TRUE(crossings[0].entering);
}

HierarchicalOracle ball() {
  return HierarchicalOracle({{std::make_shared<Sphere>(Point3{0, 0, 0}, 1.0, "ball"), Role::Material, 1}});
}

TEST(InputValidation, PolylineFarOutsideTheModelIsRefusedBeforeSampling) {
  // A polyline to y = 2^31 on a unit ball used to be cut into billions of pieces (bad_alloc).
  const std::string message = inputErrorOf([] {
    userPolylineFeatures({{{0, 0, 0}, {0, 2147483648.0, 0}}}, ball(), 0.1);
  });
  EXPECT_TRUE(contains(message, "features.polylines[0] leaves the meshed domain: point 1 (0, 2.14748e+09, 0) lies outside the "
                                "bounding box"))
      << message;
}

TEST(InputValidation, PolylineWithAnotherEdgesBrepIsRefused) {
  // Used to hang the thesis engine until the time limit: its nodes were pulled onto an edge
  // 0.5 away from the points.
  const auto edge = UserCurve::fromBrep(
      test::brepText(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0.5), gp_Pnt(0.5, 0, 0.5)).Edge()), "features.polylines[0].brep");
  const std::string message = inputErrorOf([&] {
    userPolylineFeatures({{{0, 0, 0}, {0, 0.5, 0}}}, ball(), 0.1, {edge});
  });
  EXPECT_TRUE(contains(message, "features.polylines[0] point 0 (0, 0, 0) is 0.5") &&
              contains(message, "the brep must be the edge the points were sampled from"))
      << message;
  // Its own edge passes.
  const auto own = UserCurve::fromBrep(
      test::brepText(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(0, 0.5, 0)).Edge()), "features.polylines[0].brep");
  EXPECT_FALSE(userPolylineFeatures({{{0, 0, 0}, {0, 0.5, 0}}}, ball(), 0.1, {own}).polylines.empty());
}

// An IGES file of a start and a global section (`global`, 72 columns a line) and parameter
// lines, each {parameters (64 columns), the entity's directory entry}; no directory section,
// so OpenCASCADE never reads it: its numbers are checked first, then the missing directory.
std::string igesFile(const std::string& global, const std::vector<std::pair<std::string, int>>& parameterLines) {
  auto line = [](std::string data, char section, int sequence) {
    data.resize(72, ' ');
    char number[8];
    std::snprintf(number, sizeof number, "%7d", sequence);
    return data + section + number + "\n";
  };
  std::string text = line("", 'S', 1) + line(global, 'G', 1);
  int sequence = 0;
  for (const auto& [parameters, entity] : parameterLines) {
    std::string data = parameters;
    data.resize(64, ' ');
    char pointer[9];
    std::snprintf(pointer, sizeof pointer, "%8d", entity);
    text += line(data + pointer, 'P', ++sequence);
  }
  return text + line("S0000001G0000001D0000000P" + std::to_string(sequence), 'T', 1);
}

std::string igesMessage(const std::string& name, const std::string& text) {
  return inputErrorOf([&] { readShapeFile(scratch(name, text), "input 'part'"); });
}

TEST(InputValidation, IgesNumbersThatAreNotFiniteAreRefusedBeforeReading) {
  // On 1.D999 for a line's start OpenCASCADE's IGES transfer looped until the time limit.
  const std::string line = "110,0.,0.,0.,1.5D3,1.,1.;";
  std::string message = igesMessage("inf.iges", igesFile("1H,,1H;;", {{line, 1}, {"110,1.D999,0.,0.,1.,1.,1.;", 3}}));
  EXPECT_TRUE(contains(message, "input 'part' has a number that is not finite (1.D999) in the parameters of IGES "
                                "entity DE 3: the file is damaged"))
      << message;
  // The delimiters the global section declares ("1H/" and "1H!" here), and NaN.
  message = igesMessage("nan.iges", igesFile("1H//1H!!", {{"110/0./NaN/0./1./1./1.!", 1}}));
  EXPECT_TRUE(contains(message, "not finite (NaN) in the parameters of IGES entity DE 1")) << message;
  // Strings are not numbers, also one continued on the next line; finite numbers in D form pass.
  const std::string longString = "406,1,70H" + std::string(55, 'a');
  message = igesMessage("strings.iges", igesFile("", {{line, 1}, {"406,1,12H1.D999,NaN,x;", 3},
                                                      {longString, 5}, {",1.D999,NaN,bbb;", 5}}));
  EXPECT_FALSE(contains(message, "not finite")) << message;
  // These files have no directory section: refused before OpenCASCADE reads them (next test).
  EXPECT_TRUE(contains(message, "its parameter data (line 3) comes before any directory entry")) << message;
}

TEST(InputValidation, IgesWithoutDirectoryAfterAnotherIgesInOneProcess) {
  // OpenCASCADE's IGES parser keeps the last directory entry of the previous file it read (freed
  // with that file) and files a later file's parameters under it when no directory entry came
  // first: a segfault in iges_newparam, which took the whole unit-test binary down once another
  // suite had read an IGES file. The core refuses such a file before OpenCASCADE sees it; the
  // good file read before and after it still reads.
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);
  ASSERT_TRUE(writer.AddShape(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(10, 8, 5)).Shape()));
  writer.ComputeModel();
  std::ostringstream box;
  ASSERT_TRUE(writer.Write(box));
  const std::string good = scratch("box.iges", box.str());
  const std::string noDirectory = scratch("no_directory.iges", igesFile("1H,,1H;;", {{"110,0.,0.,0.,1.,1.,1.;", 1}}));
  for (int round = 0; round < 3; ++round) {
    const BrepSolid::Loaded loaded = BrepSolid::loadFile(good, "box", BrepSolid::Grouping::Separate);
    ASSERT_EQ(loaded.solids.size(), 1u) << "round " << round;
    EXPECT_NEAR(loaded.solids[0]->volume(), 400, 1e-6 * 400) << "round " << round;
    const std::string message = inputErrorOf([&] { readShapeFile(noDirectory, "input 'part'"); });
    EXPECT_TRUE(contains(message, "input 'part' is not a readable IGES file: its parameter data (line 3) comes before "
                                  "any directory entry (D lines)"))
        << message;
  }
}

}  // namespace
}  // namespace oraclemesh

namespace oraclemesh {
namespace {

// The box [0, 10] x [0, 8] x [0, 5] (diagonal 13.75) with the tolerance of its edge `index`
// (1-based, as TopExp::MapShapes numbers it) and of that edge's vertices widened to `tolerance`,
// as OpenCASCADE's shape healing does when a face's surface does not carry the edge.
TopoDS_Shape boxWithWideEdge(int index, double tolerance) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(10, 8, 5)).Shape();
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(box, TopAbs_EDGE, edges);
  const TopoDS_Edge& edge = TopoDS::Edge(edges(index));
  BRep_Builder builder;
  builder.UpdateEdge(edge, tolerance);
  TopoDS_Vertex first, last;
  TopExp::Vertices(edge, first, last);
  builder.UpdateVertex(first, tolerance);
  builder.UpdateVertex(last, tolerance);
  return box;
}

TEST(InputValidation, ToleranceWidenedToTheModelsScaleIsRefusedNamingTheEdge) {
  // tests/data/bad/cad/box_edge_curve_misspelt.step: one plane lost its point, OpenCASCADE
  // widened three edges to 5.00005 mm; corners 5 mm apart then became one and the sharp edge
  // between them a polyline out and back (thesis engine: "internal error", Mesh_3: endless
  // edge protection).
  const std::string message = inputErrorOf([] { BrepSolid(boxWithWideEdge(1, 5.00005), "box"); });
  EXPECT_TRUE(contains(message, "input 'box': edge 1 of 12, from (0, 0, 0) to (0, 0, 5), has a tolerance of 5.00005") &&
              contains(message, "so the file is damaged there") && contains(message, "Part > Check geometry"))
      << message;
  // Just under 1 % of the diagonal passes (the shared models reach 0.015 %).
  EXPECT_NO_THROW(BrepSolid(boxWithWideEdge(1, 0.13), "box"));
}

TEST(InputValidation, EdgeWhoseCurveEndsFarFromItsVertexIsRefusedNamingIt) {
  // tests/data/bad/cad/brep_classifier_hang.brep: one changed byte in a BREP moved an edge's
  // range, and OpenCASCADE's exact classifier spent seconds on every point near it.
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(10, 8, 5)).Shape();
  TopTools_IndexedMapOfShape vertices;
  TopExp::MapShapes(box, TopAbs_VERTEX, vertices);
  BRep_Builder builder;
  const gp_Pnt corner = BRep_Tool::Pnt(TopoDS::Vertex(vertices(1)));
  builder.UpdateVertex(TopoDS::Vertex(vertices(1)), gp_Pnt(corner.X(), corner.Y(), corner.Z() + 0.5), 1e-7);
  const std::string message = inputErrorOf([&] { BrepSolid(box, "box"); });
  ASSERT_EQ(corner.Distance(gp_Pnt(0, 0, 5)), 0);  // the first vertex TopExp::MapShapes finds
  EXPECT_TRUE(contains(message, "input 'box' has edge ") && contains(message, "whose curve ends at (0, 0, 5)") &&
              contains(message, "0.5 model units from its vertex at (0, 0, 5.5) (tolerance 1e-07)") &&
              contains(message, "Part > Check geometry"))
      << message;
  // Within twice the tolerance (OpenCASCADE keeps it within once) passes.
  const TopoDS_Shape sound = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(10, 8, 5)).Shape();
  TopTools_IndexedMapOfShape soundVertices;
  TopExp::MapShapes(sound, TopAbs_VERTEX, soundVertices);
  builder.UpdateVertex(TopoDS::Vertex(soundVertices(1)), gp_Pnt(0, 0, 5 + 1e-3), 1e-3);
  EXPECT_NO_THROW(BrepSolid(sound, "box"));
}

TEST(InputValidation, SharpEdgeWhoseCornersMergeWithinTheirToleranceIsRefused) {
  // Past the load's check (the solid is validated first, the tolerance widened after): the
  // sharp-edge extraction, which merges corners within their tolerance, must not hand an
  // engine a polyline from a corner back to itself.
  const auto solid = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(10, 8, 5)).Shape(), "box");
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(solid->shape(), TopAbs_EDGE, edges);
  BRep_Builder builder;
  TopoDS_Vertex first, last;
  TopExp::Vertices(TopoDS::Edge(edges(1)), first, last);  // (0, 0, 0) to (0, 0, 5)
  builder.UpdateVertex(first, 5.5);
  builder.UpdateVertex(last, 5.5);
  const std::string message = inputErrorOf([&] { extractSharpEdges(*solid, 0, 30, 2); });
  EXPECT_TRUE(contains(message, "input 'box': sharp edge") && contains(message, "collapses: corners closer than 5.5") &&
              contains(message, "(0, 0, 0) to (0, 0, 5)") && contains(message, "Part > Check geometry"))
      << message;
  const auto sound = std::make_shared<BrepSolid>(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(10, 8, 5)).Shape(), "box");
  EXPECT_EQ(extractSharpEdges(*sound, 0, 30, 2).polylines.size(), 12u);
}

}  // namespace
}  // namespace oraclemesh
