// Per-pair interface behaviour (issue 19 item 2): the split that gives tied / contact /
// separate parts their own nodes, checked on two stacked B-rep boxes against the bonded mesh
// of the same job (the split runs after everything else that shapes the mesh, so the two
// meshes are the same until then), and the job's "interfaces" errors.
#include <BRepPrimAPI_MakeBox.hxx>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "input_errors.h"
#include "job/Pipeline.h"
#include "mesh/Topology.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

using nlohmann::json;

// Lower 10 x 10 x 10, Upper 6 x 6 x 5 standing on the rectangle x 2..8, y 3..9 of its top.
json twoBoxesJob(int order) {
  const TopoDS_Shape lower = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10, 10, 10).Shape();
  const TopoDS_Shape upper = BRepPrimAPI_MakeBox(gp_Pnt(2, 3, 10), 6, 6, 5).Shape();
  return {{"inputs",
           {{{"name", "Lower"}, {"brep", test::brepText(lower)}, {"material", 1}},
            {{"name", "Upper"}, {"brep", test::brepText(upper)}, {"material", 2}}}},
          {"criteria", {{"default", {{"cell_size", 3}, {"facet_size", 3}, {"facet_distance", 0.5}}}}},
          {"element_order", order},
          {"seed", 0}};
}

json withPair(json job, const std::string& kind) {
  job["interfaces"] = {{"pairs", {{{"between", {"Upper", "Lower"}}, {"kind", kind}}}}};
  return job;
}

JobResult run(const json& job) { return runJob(JobSpec::fromJson(job, ""), RunControl()); }

const MeshSurface& surfaceNamed(const JobResult& r, const std::string& name) {
  for (size_t i = 0; i < r.surfaces.size(); ++i)
    if (r.surface_names[i] == name) return r.surfaces[i];
  throw std::runtime_error("no surface " + name);
}

// Mid-node column of the edge between two corners (TetMesh's 01, 12, 20, 03, 13, 23).
int midColumn(int a, int b) {
  static constexpr int kColumn[4][4] = {{-1, 0, 2, 3}, {0, -1, 1, 4}, {2, 1, -1, 5}, {3, 4, 5, -1}};
  return kColumn[a][b];
}

// All nodes of a face: its corners and, for tet10, the mid nodes of its edges.
std::vector<int64_t> faceNodes(const TetMesh& mesh, const ElementFace& f) {
  std::vector<int64_t> nodes;
  const auto& c = kCalculixTetFaces[f.face];
  for (int k = 0; k < 3; ++k) nodes.push_back(mesh.tets[f.tet][c[k]]);
  if (mesh.order() == 2)
    for (int k = 0; k < 3; ++k) nodes.push_back(mesh.tet_mid_nodes[f.tet][midColumn(c[k], c[(k + 1) % 3])]);
  return nodes;
}

std::set<Point3> facePoints(const TetMesh& mesh, const ElementFace& f) {
  std::set<Point3> points;
  for (int64_t v : faceNodes(mesh, f)) points.insert(mesh.points[v]);
  return points;
}

std::set<int64_t> nodesOfMaterial(const TetMesh& mesh, int material) {
  std::set<int64_t> nodes;
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.tet_materials[t] != material) continue;
    nodes.insert(mesh.tets[t].begin(), mesh.tets[t].end());
    if (mesh.order() == 2) nodes.insert(mesh.tet_mid_nodes[t].begin(), mesh.tet_mid_nodes[t].end());
  }
  return nodes;
}

void expectSplitAlongTheInterface(int order) {
  SCOPED_TRACE("element order " + std::to_string(order));
  const JobResult bonded = run(twoBoxesJob(order));
  const JobResult tied = run(withPair(twoBoxesJob(order), "tied"));
  const TetMesh &before = bonded.mesh, &after = tied.mesh;

  // Same tets, same materials; the original points unchanged, one copy per interface node.
  ASSERT_EQ(after.tets.size(), before.tets.size());
  EXPECT_EQ(after.tet_materials, before.tet_materials);
  std::set<int64_t> interfaceNodes;
  for (const ElementFace& f : surfaceNamed(bonded, "Interface_Lower_Upper").faces)
    for (int64_t v : faceNodes(before, f)) interfaceNodes.insert(v);
  ASSERT_GT(interfaceNodes.size(), 10u);
  EXPECT_EQ(after.points.size(), before.points.size() + interfaceNodes.size());
  for (size_t i = 0; i < before.points.size(); ++i) ASSERT_EQ(after.points[i], before.points[i]) << i;
  EXPECT_EQ(tied.report["interface_split"]["corner_copies"].get<int64_t>() +
                tied.report["interface_split"]["mid_copies"].get<int64_t>(),
            static_cast<int64_t>(interfaceNodes.size()));
  EXPECT_EQ(after.vertex_dimension.size(), after.points.size());

  // The parts share no node any more.
  const std::set<int64_t> lower = nodesOfMaterial(after, 1), upper = nodesOfMaterial(after, 2);
  std::vector<int64_t> common;
  std::set_intersection(lower.begin(), lower.end(), upper.begin(), upper.end(), std::back_inserter(common));
  EXPECT_TRUE(common.empty()) << common.size() << " nodes shared";

  // Both sides of the interface, each from its own part's tets, face for face at the same places.
  const MeshSurface& front = surfaceNamed(tied, "Interface_Lower_Upper");
  const MeshSurface& back = surfaceNamed(tied, "Interface_Upper_Lower");
  EXPECT_EQ(front.material, 1);
  EXPECT_EQ(back.material, 2);
  ASSERT_EQ(front.faces.size(), back.faces.size());
  std::multiset<std::set<Point3>> frontFaces, backFaces;
  for (const ElementFace& f : front.faces) {
    EXPECT_EQ(after.tet_materials[f.tet], 1);
    frontFaces.insert(facePoints(after, f));
  }
  for (const ElementFace& f : back.faces) {
    EXPECT_EQ(after.tet_materials[f.tet], 2);
    backFaces.insert(facePoints(after, f));
  }
  EXPECT_TRUE(frontFaces == backFaces);
  EXPECT_EQ(frontFaces.begin()->size(), order == 2 ? 6u : 3u);
  EXPECT_NEAR(front.area, 36.0, 36e-9);
  EXPECT_NEAR(back.area, 36.0, 36e-9);
  // ...and in the split mesh they are faces of one tet each: the parts no longer share them.
  std::map<std::array<int64_t, 3>, int> uses;
  for (const auto& t : after.tets)
    for (const auto& c : kCalculixTetFaces) {
      std::array<int64_t, 3> key = {t[c[0]], t[c[1]], t[c[2]]};
      std::sort(key.begin(), key.end());
      ++uses[key];
    }
  for (const MeshSurface* s : {&front, &back})
    for (const ElementFace& f : s->faces) {
      const auto n = faceNodes(after, f);
      std::array<int64_t, 3> key = {n[0], n[1], n[2]};
      std::sort(key.begin(), key.end());
      EXPECT_EQ(uses[key], 1);
    }

  // A valid mesh: no open boundary, mid nodes consistent, volumes per material unchanged.
  EXPECT_TRUE(checkConformity(after).ok()) << tied.report["conformity"].dump();
  EXPECT_EQ(tied.report["volume_per_material"], bonded.report["volume_per_material"]);
  EXPECT_NEAR(tied.report["volume_per_material"]["2"].get<double>(), 180.0, 180e-9);
  EXPECT_EQ(featureEdgesNotTetEdges(after), 0);
  for (const BoundaryTriangle& tri : after.boundary) {
    const std::set<int64_t>& side = tri.material_in == 1 ? lower : upper;
    for (int64_t v : tri.v) EXPECT_TRUE(side.count(v)) << "boundary triangle vertex " << v;
  }

  // The report names the pair's kind and both sides.
  ASSERT_EQ(tied.report["interfaces"].size(), 1u);
  const json& entry = tied.report["interfaces"][0];
  EXPECT_EQ(entry["kind"], "tied");
  EXPECT_EQ(entry["surfaces"], json::array({"Interface_Lower_Upper", "Interface_Upper_Lower"}));
  EXPECT_EQ(bonded.report["interfaces"][0]["kind"], "bonded");
  EXPECT_EQ(bonded.report["interface_split"]["corner_copies"], 0);
}

TEST(InterfaceSplit, TiedBoxesGetOwnNodesAlongTheirCommonFaceTet4) { expectSplitAlongTheInterface(1); }
TEST(InterfaceSplit, TiedBoxesGetOwnNodesAlongTheirCommonFaceTet10) { expectSplitAlongTheInterface(2); }

TEST(InterfaceSplit, BondedSettingGivesTheSameMeshAsNoSetting) {
  const JobResult plain = run(twoBoxesJob(2));
  json job = withPair(twoBoxesJob(2), "bonded");
  job["interfaces"]["default"] = "bonded";
  const JobResult bonded = run(job);
  EXPECT_EQ(bonded.mesh.points, plain.mesh.points);
  EXPECT_EQ(bonded.mesh.tets, plain.mesh.tets);
  EXPECT_EQ(bonded.mesh.tet_mid_nodes, plain.mesh.tet_mid_nodes);
  EXPECT_EQ(bonded.mesh.feature_edges, plain.mesh.feature_edges);
  EXPECT_EQ(bonded.surface_names, plain.surface_names);
}

// The INP of a contact pair: the two sides as surfaces and the CalculiX cards joining them.
TEST(InterfaceSplit, ContactPairIsWrittenAsCalculixContact) {
  const std::string inp = (std::filesystem::temp_directory_path() / "oraclemesh_split_contact.inp").string();
  json job = twoBoxesJob(2);
  job["interfaces"] = {{"default", "contact"},
                       {"pairs", {{{"between", {"Lower", "Upper"}}, {"kind", "contact"}, {"friction", 0.2},
                                   {"master", "Lower"}}}}};
  job["output"] = {{"files", {inp}}};
  const JobResult r = run(job);
  std::ifstream file(inp);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  for (const char* card : {"*SURFACE, NAME=Interface_Lower_Upper, TYPE=ELEMENT\n",
                           "*SURFACE, NAME=Interface_Upper_Lower, TYPE=ELEMENT\n",
                           "*SURFACE INTERACTION, NAME=Contact_Lower_Upper\n", "*FRICTION\n0.2, ",
                           "*CONTACT PAIR, INTERACTION=Contact_Lower_Upper, TYPE=SURFACE TO SURFACE\n"
                           "Interface_Upper_Lower, Interface_Lower_Upper\n"})
    EXPECT_NE(text.find(card), std::string::npos) << card;
  EXPECT_EQ(text.find("*STEP"), std::string::npos);
  EXPECT_EQ(r.report["interfaces"][0]["master"], "Interface_Lower_Upper");
  EXPECT_EQ(r.report["interfaces"][0]["friction"], 0.2);
  // No slope in the job: the steel default 2.5 E / h, h the mean edge of the interface faces.
  double edges = 0;
  const MeshSurface& front = surfaceNamed(r, "Interface_Lower_Upper");
  for (const ElementFace& f : front.faces)
    for (int k = 0; k < 3; ++k) {
      const auto& c = kCalculixTetFaces[f.face];
      const Point3 &a = r.mesh.points[r.mesh.tets[f.tet][c[k]]], &b = r.mesh.points[r.mesh.tets[f.tet][c[(k + 1) % 3]]];
      edges += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    }
  const double h = edges / (3.0 * static_cast<double>(front.faces.size()));
  EXPECT_NEAR(r.report["interfaces"][0]["contact_stiffness"].get<double>(), 2.5 * 210000 / h, 1e-9 * 210000 / h);
  EXPECT_NE(text.find("slope 2.5 E / h for steel"), std::string::npos);
  std::filesystem::remove(inp);
}

std::string fileText(const std::string& path) {
  std::ifstream file(path);
  return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

// The job's contact slope reaches the *SURFACE BEHAVIOR card and the report: the pair's own,
// else interfaces.contact_stiffness for every contact pair.
TEST(InterfaceSplit, ContactStiffnessFromTheJobIsTheCardsSlope) {
  const std::string inp = (std::filesystem::temp_directory_path() / "oraclemesh_split_stiffness.inp").string();
  json job = twoBoxesJob(1);
  job["interfaces"] = {{"contact_stiffness", 1234.5},
                       {"pairs", {{{"between", {"Lower", "Upper"}}, {"kind", "contact"}, {"contact_stiffness", 25.0},
                                   {"friction", 0.3}}}}};
  job["output"] = {{"files", {inp}}};
  JobResult r = run(job);
  std::string text = fileText(inp);
  // The stick slope of the friction: 1/100 of the normal slope.
  EXPECT_NE(text.find("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n25\n*FRICTION\n0.3, 0.25\n"), std::string::npos);
  EXPECT_NE(text.find("slope from the job's interfaces contact_stiffness"), std::string::npos);
  EXPECT_EQ(r.report["interfaces"][0]["contact_stiffness"], 25.0);

  job["interfaces"]["pairs"][0].erase("contact_stiffness");
  r = run(job);
  text = fileText(inp);
  EXPECT_NE(text.find("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1234.5\n"), std::string::npos);
  EXPECT_EQ(r.report["interfaces"][0]["contact_stiffness"], 1234.5);

  // The default slope also applies to pairs in contact through interfaces.default.
  job["interfaces"] = {{"default", "contact"}, {"contact_stiffness", 777.0}};
  r = run(job);
  text = fileText(inp);
  EXPECT_NE(text.find("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n777\n"), std::string::npos);
  EXPECT_EQ(r.report["interfaces"][0]["contact_stiffness"], 777.0);
  std::filesystem::remove(inp);
}

// A 10 mm cube A with B beside it (x 10..20) and C on top of it (z 10..20): A-B and A-C share
// a face, B-C only the edge x = 10, z = 10. With A-C tied and the rest bonded, the nodes on
// that edge belong to all three and stay shared by A and C through B; the report says so.
TEST(InterfaceSplit, PartsJoinedThroughAThirdBondedToBothAreReported) {
  auto box = [](double x, double z, const char* name, int material) {
    return json{{"name", name}, {"brep", test::brepText(BRepPrimAPI_MakeBox(gp_Pnt(x, 0, z), 10, 10, 10).Shape())},
                {"material", material}};
  };
  json job = {{"inputs", {box(0, 0, "A", 1), box(10, 0, "B", 2), box(0, 10, "C", 3)}},
              {"criteria", {{"default", {{"cell_size", 3}, {"facet_size", 3}}}}},
              {"element_order", 1},
              {"seed", 0},
              {"interfaces", {{"pairs", {{{"between", {"A", "C"}}, {"kind", "tied"}}}}}}};
  const JobResult r = run(job);
  const TetMesh& mesh = r.mesh;
  // The corner nodes A and C still share: exactly the nodes on the edge of all three.
  const std::set<int64_t> a = nodesOfMaterial(mesh, 1), c = nodesOfMaterial(mesh, 3), b = nodesOfMaterial(mesh, 2);
  std::vector<int64_t> common;
  std::set_intersection(a.begin(), a.end(), c.begin(), c.end(), std::back_inserter(common));
  ASSERT_GE(common.size(), 4u);  // the 10 mm edge at size 3 has at least 4 nodes
  for (int64_t v : common) {
    EXPECT_NEAR(mesh.points[v][0], 10, 1e-9);
    EXPECT_NEAR(mesh.points[v][2], 10, 1e-9);
    EXPECT_TRUE(b.count(v)) << v;
  }
  // ...while the rest of their common face is split.
  EXPECT_GT(r.report["interface_split"]["corner_copies"].get<int64_t>(), 10);
  const json& kept = r.report["interface_split"]["kept_joined"];
  ASSERT_EQ(kept.size(), 1u) << kept.dump();
  EXPECT_EQ(kept[0]["parts"], json::array({"A", "C"}));
  EXPECT_EQ(kept[0]["through"], json::array({"B"}));
  EXPECT_EQ(kept[0]["nodes"].get<size_t>(), common.size());
  std::vector<std::string> warnings;
  for (const json& w : r.report["warnings"])
    if (w.get<std::string>().find("stay joined") != std::string::npos) warnings.push_back(w.get<std::string>());
  ASSERT_EQ(warnings.size(), 1u) << r.report["warnings"].dump();
  EXPECT_EQ(warnings[0], "interfaces: the parts 'A' and 'C' (\"tied\") stay joined at " + std::to_string(common.size()) +
                             " nodes, where both meet 'B', bonded to both: a node shared with a part bonded to both "
                             "cannot be split between them; make 'A'-'B' or 'B'-'C' not bonded to part them there too");

  // The tie leaves the shared nodes out (CalculiX rejects a node tied to itself): its slave
  // side is a node surface over the slave faces' other nodes.
  const json& tie = r.report["interfaces"][1];
  ASSERT_EQ(tie["parts"], json::array({"A", "C"})) << r.report["interfaces"].dump();
  ASSERT_EQ(tie["slave_node_surface"], "Tie_A_C_Slave");
  std::set<int64_t> slaveFaceNodes;
  for (const ElementFace& f : surfaceNamed(r, tie["slave"].get<std::string>()).faces)
    for (int64_t v : faceNodes(mesh, f)) slaveFaceNodes.insert(v);
  EXPECT_EQ(tie["slave_nodes"].get<size_t>() + common.size(), slaveFaceNodes.size());
  const std::string inp = (std::filesystem::temp_directory_path() / "oraclemesh_split_three.inp").string();
  json written = job;
  written["output"] = {{"files", {inp}}};
  run(written);
  const std::string text = fileText(inp);
  const std::string nsetCard = "*NSET, NSET=Tie_A_C_Slave\n";
  const size_t nset = text.find(nsetCard);
  ASSERT_NE(nset, std::string::npos);
  const size_t surface = text.find("*SURFACE, NAME=Tie_A_C_Slave, TYPE=NODE\nTie_A_C_Slave\n", nset);
  ASSERT_NE(surface, std::string::npos);
  std::set<int64_t> listed;
  const size_t idsStart = nset + nsetCard.size();
  std::string idText = text.substr(idsStart, surface - idsStart);
  std::replace(idText.begin(), idText.end(), '\n', ',');  // 8 ids a line
  std::istringstream ids(idText);
  for (std::string id; std::getline(ids, id, ',');)
    if (!id.empty()) listed.insert(std::stoll(id) - 1);
  std::set<int64_t> expected;
  std::set_difference(slaveFaceNodes.begin(), slaveFaceNodes.end(), common.begin(), common.end(),
                      std::inserter(expected, expected.end()));
  EXPECT_EQ(listed, expected);
  EXPECT_NE(text.find("ADJUST=NO\nTie_A_C_Slave, " + tie["master"].get<std::string>() + "\n"), std::string::npos);
  std::filesystem::remove(inp);

  // With B-C not bonded either, nothing keeps A and C joined.
  job["interfaces"]["pairs"].push_back({{"between", {"B", "C"}}, {"kind", "separate"}});
  const JobResult apart = run(job);
  EXPECT_TRUE(apart.report["interface_split"]["kept_joined"].empty());
  const std::set<int64_t> a2 = nodesOfMaterial(apart.mesh, 1), c2 = nodesOfMaterial(apart.mesh, 3);
  common.clear();
  std::set_intersection(a2.begin(), a2.end(), c2.begin(), c2.end(), std::back_inserter(common));
  EXPECT_TRUE(common.empty()) << common.size();
}

std::string parseError(const json& job) {
  return test::inputErrorOf([&] { JobSpec::fromJson(job, ""); });
}

TEST(InterfaceSplit, InterfaceSettingErrorsNameThePathAndTheFix) {
  json job = {{"inputs", {{{"name", "ball"}, {"sphere", {{"center", {0, 0, 0}}, {"radius", 1}}}}}}};
  job["interfaces"] = {{"default", "glued"}};
  EXPECT_EQ(parseError(job), "interfaces.default = \"glued\" is not an interface kind: use \"bonded\" (shared nodes), "
                             "\"tied\", \"contact\" or \"separate\"");
  job["interfaces"] = {{"pairs", {{{"between", {"a", "b"}}, {"kind", "tied"}}, {{"between", {"b", "a"}}, {"kind", "contact"}}}}};
  EXPECT_EQ(parseError(job), "interfaces.pairs[1] repeats the pair 'b', 'a' of interfaces.pairs[0]: give each pair once");
  job["interfaces"] = {{"pairs", {{{"between", {"a", "b"}}, {"kind", "contact"}, {"friction", -0.1}}}}};
  EXPECT_EQ(parseError(job), "interfaces.pairs[0].friction = -0.1 is negative: give a Coulomb friction coefficient "
                             ">= 0 (0 = frictionless)");
  job["interfaces"] = {{"pairs", {{{"between", {"a", "b"}}, {"kind", "tied"}, {"friction", 0.1}}}}};
  EXPECT_NE(parseError(job).find("interfaces.pairs[0].friction belongs to kind \"contact\" only"), std::string::npos);
  const std::string slopeFix = ": give the contact pressure per unit of overclosure (force / length^3 in the model's "
                               "units, e.g. N/mm^3), > 0";
  job["interfaces"] = {{"contact_stiffness", 0}};
  EXPECT_EQ(parseError(job), "interfaces.contact_stiffness = 0 is not a positive finite number" + slopeFix);
  job["interfaces"] = {{"contact_stiffness", "stiff"}};
  EXPECT_EQ(parseError(job), "interfaces.contact_stiffness must be a number, got \"stiff\"" + slopeFix);
  job["interfaces"] = {{"pairs", {{{"between", {"a", "b"}}, {"kind", "contact"}, {"contact_stiffness", -5}}}}};
  EXPECT_EQ(parseError(job), "interfaces.pairs[0].contact_stiffness = -5 is not a positive finite number" + slopeFix);
  job["interfaces"] = {{"pairs", {{{"between", {"a", "b"}}, {"kind", "tied"}, {"contact_stiffness", 5}}}}};
  EXPECT_NE(parseError(job).find("interfaces.pairs[0].contact_stiffness belongs to kind \"contact\" only"),
            std::string::npos);
  job["interfaces"] = {{"pairs", {{{"between", {"a", "a"}}, {"kind", "tied"}}}}};
  EXPECT_NE(parseError(job).find("interfaces.pairs[0].between names part 'a' twice"), std::string::npos);
  job["interfaces"] = {{"pairs", {{{"between", {"a"}}, {"kind", "tied"}}}}};
  EXPECT_NE(parseError(job).find("interfaces.pairs[0].between must be the names of two parts"), std::string::npos);
  const std::string nonFinite = test::inputErrorOf([] {
    JobSpec::fromJsonText(R"({"inputs": [{"sphere": {"center": [0, 0, 0], "radius": 1}}],
                              "interfaces": {"pairs": [{"between": ["a", "b"], "kind": "contact", "friction": 1e999}]}})",
                          "");
  });
  EXPECT_NE(nonFinite.find("numbers must be finite"), std::string::npos) << nonFinite;

  // A part name that is not in the model: known after loading, before meshing.
  json boxes = withPair(twoBoxesJob(1), "tied");
  boxes["interfaces"]["pairs"][0]["between"][1] = "Lowr";
  EXPECT_EQ(test::inputErrorOf([&] { run(boxes); }),
            "interfaces.pairs[0].between[1] = 'Lowr' is no part of the model: the parts are 'Lower', 'Upper' (as "
            "report.inputs and report.interfaces name them; inputs of one material id are one part, named with '+')");
}

}  // namespace
}  // namespace oraclemesh
