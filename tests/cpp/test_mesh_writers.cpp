// Mesh files (src/core/mesh/Writers): written, read back by small parsers here, compared
// bit for bit. tests/python/test_writers_meshio.py has meshio and CalculiX read the files a
// job writes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "Error.h"
#include "mesh/SecondOrder.h"
#include "mesh/Writers.h"
#include "mesh_fixtures.h"

namespace oraclemesh {
namespace {

std::string outputDir() {
  const char* dir = std::getenv("ORACLEMESH_TEST_OUTPUT");
  return dir && *dir ? dir : "/tmp";
}

// A scratch path of this process, so that parallel ctest runs do not share files.
std::string scratchPath(const std::string& name) {
  return outputDir() + "/mesh_writers_" + std::to_string(::getpid()) + "_" + name;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The cube with coordinates that have no short decimal form, so that a lossy writer shows.
TetMesh roundTripMesh(int order) {
  TetMesh mesh = test::kuhnCube(/*two_materials=*/true, /*size=*/0.1);
  for (Point3& p : mesh.points) p = p + Point3{1.0 / 3, -2.0 / 7, 1e-5 / 3};
  mesh.tet_materials = {3, 3, 3, 8, 8, 8};
  if (order == 2) makeSecondOrder(mesh, [](int64_t, int64_t, const Point3& mid) { return mid; });
  return mesh;
}

// Numbers between <DataArray ... Name="name" ...> and </DataArray>.
template <typename T>
std::vector<T> vtuArray(const std::string& xml, const std::string& name) {
  const size_t tag = xml.find("Name=\"" + name + "\"");
  if (tag == std::string::npos) return {};
  const size_t begin = xml.find('>', tag) + 1;
  const size_t end = xml.find("</DataArray>", begin);
  std::istringstream in(xml.substr(begin, end - begin));
  std::vector<T> values;
  T v;
  while (in >> v) values.push_back(v);
  return values;
}

TEST(MeshWriters, VtuRoundTripIsExact) {
  for (int order : {1, 2}) {
    const TetMesh mesh = roundTripMesh(order);
    const std::string path = scratchPath("roundtrip.vtu");
    writeVtu(path, mesh);
    const std::string xml = readFile(path);
    std::remove(path.c_str());
    EXPECT_NE(xml.find("NumberOfPoints=\"" + std::to_string(mesh.points.size()) + "\""), std::string::npos);
    EXPECT_NE(xml.find("NumberOfCells=\"6\""), std::string::npos);

    const auto coords = vtuArray<double>(xml, "Points");
    ASSERT_EQ(coords.size(), 3 * mesh.points.size());
    for (size_t i = 0; i < mesh.points.size(); ++i)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(coords[3 * i + k], mesh.points[i][k]) << "point " << i;

    const int nodesPerCell = order == 2 ? 10 : 4;
    const auto connectivity = vtuArray<int64_t>(xml, "connectivity");
    ASSERT_EQ(connectivity.size(), nodesPerCell * mesh.tets.size());
    for (size_t t = 0; t < mesh.tets.size(); ++t) {
      for (int i = 0; i < 4; ++i) EXPECT_EQ(connectivity[nodesPerCell * t + i], mesh.tets[t][i]);
      if (order == 2) {  // VTK_QUADRATIC_TETRA: mid nodes 01, 12, 20, 03, 13, 23 like TetMesh
        for (int e = 0; e < 6; ++e) EXPECT_EQ(connectivity[nodesPerCell * t + 4 + e], mesh.tet_mid_nodes[t][e]);
      }
    }
    const auto offsets = vtuArray<int64_t>(xml, "offsets");
    ASSERT_EQ(offsets.size(), mesh.tets.size());
    EXPECT_EQ(offsets.back(), static_cast<int64_t>(connectivity.size()));
    for (int type : vtuArray<int>(xml, "types")) EXPECT_EQ(type, order == 2 ? 24 : 10);
    EXPECT_EQ(vtuArray<int>(xml, "material"), mesh.tet_materials);
    EXPECT_EQ(vtuArray<int>(xml, "vertex_dimension"), mesh.vertex_dimension);
  }
}

struct InpFile {
  std::map<int64_t, Point3> nodes;
  struct Element {
    std::string type, elset;
    std::vector<int64_t> nodes;
  };
  std::map<int64_t, Element> elements;
  std::map<std::string, std::vector<std::string>> elsetsOfSets;  // *ELSET listing set names
};

InpFile parseInp(const std::string& text) {
  InpFile inp;
  std::istringstream in(text);
  std::string line, keyword, type, elset;
  auto param = [](const std::string& l, const std::string& name) {
    const size_t at = l.find(name + "=");
    if (at == std::string::npos) return std::string();
    const size_t begin = at + name.size() + 1;
    return l.substr(begin, l.find(',', begin) - begin);
  };
  while (std::getline(in, line)) {
    if (line.rfind("**", 0) == 0 || line.empty()) continue;
    if (line[0] == '*') {
      keyword = line.substr(0, line.find(','));
      type = param(line, "TYPE");
      elset = param(line, "ELSET");
      continue;
    }
    std::vector<std::string> fields;
    std::istringstream l(line);
    for (std::string f; std::getline(l, f, ',');) fields.push_back(f);
    if (keyword == "*NODE") {
      // strtod, not stod: stod throws on subnormal numbers.
      inp.nodes[std::stoll(fields[0])] = {std::strtod(fields[1].c_str(), nullptr), std::strtod(fields[2].c_str(), nullptr),
                                          std::strtod(fields[3].c_str(), nullptr)};
    } else if (keyword == "*ELEMENT") {
      InpFile::Element& e = inp.elements[std::stoll(fields[0])];
      e.type = type;
      e.elset = elset;
      for (size_t i = 1; i < fields.size(); ++i) e.nodes.push_back(std::stoll(fields[i]));
    } else if (keyword == "*ELSET") {
      inp.elsetsOfSets[elset].push_back(fields[0]);
    }
  }
  return inp;
}

TEST(MeshWriters, InpRoundTripIsExactWithOneElsetPerMaterial) {
  for (int order : {1, 2}) {
    const TetMesh mesh = roundTripMesh(order);
    const std::string path = scratchPath("roundtrip.inp");
    writeInp(path, mesh);
    const InpFile inp = parseInp(readFile(path));
    std::remove(path.c_str());
    ASSERT_EQ(inp.nodes.size(), mesh.points.size());
    // Exact except where CalculiX' 20-character limit rounds (here: z = 1e-5 / 3).
    for (size_t i = 0; i < mesh.points.size(); ++i)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(inp.nodes.at(i + 1)[k], mesh.points[i][k], 5e-14 * std::fabs(mesh.points[i][k])) << "node " << i + 1;
    ASSERT_EQ(inp.elements.size(), mesh.tets.size());
    for (size_t t = 0; t < mesh.tets.size(); ++t) {
      const InpFile::Element& e = inp.elements.at(t + 1);
      EXPECT_EQ(e.type, order == 2 ? "C3D10" : "C3D4");
      EXPECT_EQ(e.elset, "Material" + std::to_string(mesh.tet_materials[t]));
      ASSERT_EQ(e.nodes.size(), order == 2 ? 10u : 4u);
      // Corners in TetMesh's positive order (ccx rejects negative volumes), then the mid
      // nodes of edges 12, 23, 31, 14, 24, 34 (one-based) = TetMesh's 01, 12, 20, 03, 13, 23.
      for (int i = 0; i < 4; ++i) EXPECT_EQ(e.nodes[i], mesh.tets[t][i] + 1);
      if (order == 2) {
        for (int k = 0; k < 6; ++k) EXPECT_EQ(e.nodes[4 + k], mesh.tet_mid_nodes[t][k] + 1);
      }
    }
    EXPECT_EQ(inp.elsetsOfSets.at("Eall"), (std::vector<std::string>{"Material3", "Material8"}));
  }
}

TEST(MeshWriters, InpCoordinatesFitCalculixTwentyCharacterFields) {
  TetMesh mesh = test::cornerTet();
  const std::vector<double> values{0.1, 1.0 / 3, -0.012345678901234567, 1e-5 / 3, -1.2345678901234567e-300,
                                   123456789.12345678, -1e20 / 3, 5e-324, -0.0, 1e15 + 0.5};
  // The writer does not care about the tet's shape, only about the numbers.
  for (size_t i = 0; i < 12; ++i) mesh.points[i / 3][i % 3] = values[i % values.size()];
  const std::string path = scratchPath("widths.inp");
  writeInp(path, mesh);
  const std::string text = readFile(path);
  std::remove(path.c_str());
  const InpFile inp = parseInp(text);
  for (size_t i = 0; i < mesh.points.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double x = mesh.points[i][k];
      // 13 significant digits at worst (negative, three-digit exponent).
      EXPECT_NEAR(inp.nodes.at(i + 1)[k], x, 5e-13 * std::fabs(x)) << x;
    }
  // Short exact forms stay exact and short.
  EXPECT_NE(text.find(", 0.1, "), std::string::npos);
  std::istringstream lines(text);
  bool inNodes = false;
  for (std::string line; std::getline(lines, line);) {
    if (line[0] == '*') inNodes = line.rfind("*NODE", 0) == 0;
    if (!inNodes || line[0] == '*') continue;
    std::istringstream fields(line);
    std::string field;
    std::getline(fields, field, ',');
    while (std::getline(fields, field, ',')) {
      field.erase(0, field.find_first_not_of(' '));
      EXPECT_LE(field.size(), 20u) << field;
    }
  }
}

TEST(MeshWriters, NonFiniteCoordinateIsRefused) {
  TetMesh mesh = test::cornerTet();
  mesh.points[2][1] = std::nan("");
  EXPECT_THROW(writeInp(scratchPath("nan.inp"), mesh), Error);
  EXPECT_THROW(writeVtu(scratchPath("nan.vtu"), mesh), Error);
  std::remove(scratchPath("nan.inp").c_str());
  std::remove(scratchPath("nan.vtu").c_str());
}

TEST(MeshWriters, DispatchOnExtensionIgnoresCase) {
  const TetMesh mesh = roundTripMesh(1);
  const std::string vtu = scratchPath("upper.VTU"), inp = scratchPath("upper.Inp");
  writeMeshFile(vtu, mesh);
  writeMeshFile(inp, mesh);
  EXPECT_NE(readFile(vtu).find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(readFile(inp).find("*NODE"), std::string::npos);
  std::remove(vtu.c_str());
  std::remove(inp.c_str());
}

TEST(MeshWriters, UnknownExtensionNamesPathAndSupportedOnes) {
  const TetMesh mesh = roundTripMesh(1);
  for (const std::string path : {"/tmp/out.stl", "/tmp/noextension", "/tmp/dir.vtu/mesh"}) {
    try {
      writeMeshFile(path, mesh);
      FAIL() << "no error for " << path;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(message.find(".vtu"), std::string::npos) << message;
      EXPECT_NE(message.find(".inp"), std::string::npos) << message;
    }
  }
}

TEST(MeshWriters, UnwritablePathIsAnErrorNamingIt) {
  const TetMesh mesh = roundTripMesh(1);
  for (const std::string path : {"/nonexistent-folder/mesh.vtu", "/nonexistent-folder/mesh.inp"}) {
    try {
      writeMeshFile(path, mesh);
      FAIL() << "no error for " << path;
    } catch (const InputError&) {
      FAIL() << "an unwritable path is not an input error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST(MeshWriters, FullDiskIsAnError) {
  if (!std::ifstream("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  EXPECT_THROW(writeVtu("/dev/full", roundTripMesh(2)), Error);
}

}  // namespace
}  // namespace oraclemesh
