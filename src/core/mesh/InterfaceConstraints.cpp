#include "mesh/InterfaceConstraints.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "mesh/Quality.h"

namespace oraclemesh {

namespace {

double meanTetVolume(const TetMesh& mesh, const MeshSurface& surface) {
  double sum = 0;
  for (const ElementFace& f : surface.faces) {
    const auto& t = mesh.tets[f.tet];
    sum += tetVolume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
  }
  return surface.faces.empty() ? 0 : sum / static_cast<double>(surface.faces.size());
}

double meanFaceEdge(const TetMesh& mesh, const MeshSurface& surface) {
  double sum = 0;
  for (const ElementFace& f : surface.faces) {
    const auto& corners = kCalculixTetFaces[f.face];
    for (int k = 0; k < 3; ++k) {
      const Point3& a = mesh.points[mesh.tets[f.tet][corners[k]]];
      const Point3& b = mesh.points[mesh.tets[f.tet][corners[(k + 1) % 3]]];
      sum += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    }
  }
  return surface.faces.empty() ? 1 : sum / (3.0 * static_cast<double>(surface.faces.size()));
}

constexpr double kSteelYoungsModulus = 210000;  // N/mm^2

double shortestFaceEdge(const TetMesh& mesh, const MeshSurface& surface) {
  double shortest = std::numeric_limits<double>::infinity();
  for (const ElementFace& f : surface.faces) {
    const auto& corners = kCalculixTetFaces[f.face];
    for (int k = 0; k < 3; ++k) {
      const Point3& a = mesh.points[mesh.tets[f.tet][corners[k]]];
      const Point3& b = mesh.points[mesh.tets[f.tet][corners[(k + 1) % 3]]];
      shortest = std::min(shortest, std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                              (a[2] - b[2]) * (a[2] - b[2])));
    }
  }
  return shortest;
}

// Nodes of the surface's faces: corners and, for tet10, the mid nodes of the faces' edges.
std::set<int64_t> surfaceNodes(const TetMesh& mesh, const MeshSurface& surface) {
  std::set<int64_t> nodes;
  for (const ElementFace& f : surface.faces) {
    const auto& corners = kCalculixTetFaces[f.face];
    for (int k = 0; k < 3; ++k) nodes.insert(mesh.tets[f.tet][corners[k]]);
    if (mesh.order() != 2) continue;
    auto onFace = [&](int corner) { return std::find(corners.begin(), corners.end(), corner) != corners.end(); };
    for (int e = 0; e < 6; ++e)
      if (onFace(kTetEdgeCorners[e][0]) && onFace(kTetEdgeCorners[e][1])) nodes.insert(mesh.tet_mid_nodes[f.tet][e]);
  }
  return nodes;
}

// The slave face nodes the master part's tets also use (see InterfaceConstraint::slave_nodes).
void dropNodesOfTheMaster(const TetMesh& mesh, const MeshSurface& slave, InterfaceConstraint& c) {
  const std::set<int64_t> faceNodes = surfaceNodes(mesh, slave);
  std::set<int64_t> shared;
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.tet_materials[t] != c.master_material) continue;
    for (int64_t v : mesh.tets[t])
      if (faceNodes.count(v)) shared.insert(v);
    if (mesh.order() == 2)
      for (int64_t v : mesh.tet_mid_nodes[t])
        if (faceNodes.count(v)) shared.insert(v);
  }
  if (shared.empty()) return;
  for (int64_t v : faceNodes)
    if (!shared.count(v)) c.slave_nodes.push_back(v);
  c.slave_nodes_name = inpName(c.name + "_Slave");
}

}  // namespace

std::vector<InterfaceConstraint> interfaceConstraints(const TetMesh& mesh, const std::vector<MeshSurface>& surfaces,
                                                      const MaterialNames& names, const InterfacePlan& plan) {
  std::map<std::pair<int, int>, const MeshSurface*> side;  // (faces' material, other material)
  std::map<const MeshSurface*, std::string> nameOf;  // as the *SURFACE blocks name them
  const std::vector<std::string> unique = surfaceNames(names, surfaces);
  for (size_t i = 0; i < surfaces.size(); ++i) {
    const MeshSurface& s = surfaces[i];
    nameOf[&s] = unique[i];
    if (s.other_material != 0) side[{s.material, s.other_material}] = &s;
  }
  std::vector<InterfaceConstraint> result;
  for (const auto& [pair, front] : side) {
    const auto [a, b] = pair;
    if (a > b) continue;
    const InterfaceBehaviour behaviour = plan.between(a, b);
    if (behaviour.kind != InterfaceKind::Tied && behaviour.kind != InterfaceKind::Contact) continue;
    const auto backIt = side.find({b, a});
    if (backIt == side.end()) continue;
    const MeshSurface* back = backIt->second;
    InterfaceConstraint c;
    c.material = a;
    c.other_material = b;
    c.behaviour = behaviour;
    if (behaviour.master_material == a || behaviour.master_material == b)
      c.master_material = behaviour.master_material;
    else
      c.master_material = meanTetVolume(mesh, *back) > meanTetVolume(mesh, *front) ? b : a;
    c.slave_material = c.master_material == a ? b : a;
    const MeshSurface* master = c.master_material == a ? front : back;
    const MeshSurface* slave = c.master_material == a ? back : front;
    c.master = nameOf.at(master);
    c.slave = nameOf.at(slave);
    c.name = inpName(std::string(behaviour.kind == InterfaceKind::Tied ? "Tie_" : "Contact_") +
                     materialName(names, a) + "_" + materialName(names, b));
    c.position_tolerance = 0.01 * shortestFaceEdge(mesh, *front);
    if (behaviour.kind == InterfaceKind::Tied) dropNodesOfTheMaster(mesh, *slave, c);
    c.contact_stiffness_given = behaviour.contact_stiffness > 0;
    c.contact_stiffness = c.contact_stiffness_given ? behaviour.contact_stiffness
                                                    : 2.5 * kSteelYoungsModulus / meanFaceEdge(mesh, *front);
    result.push_back(c);
  }
  return result;
}

std::string calculixInterfaceCards(const std::vector<InterfaceConstraint>& constraints) {
  std::string cards;
  char line[1024];  // three names of up to 80 characters and the comments
  for (const InterfaceConstraint& c : constraints) {
    if (c.behaviour.kind == InterfaceKind::Tied) {
      std::string slave = c.slave;
      if (!c.slave_nodes_name.empty()) {
        slave = c.slave_nodes_name;
        std::snprintf(line, sizeof line,
                      "** %s: the slave face nodes but those the master part shares (joined through a part "
                      "bonded to both)\n*NSET, NSET=%s\n",
                      c.name.c_str(), slave.c_str());
        cards += line;
        for (size_t i = 0; i < c.slave_nodes.size(); ++i)
          cards += std::to_string(c.slave_nodes[i] + 1) + (i + 1 == c.slave_nodes.size() || i % 8 == 7 ? "\n" : ", ");
        cards += "*SURFACE, NAME=" + slave + ", TYPE=NODE\n" + slave + "\n";
      }
      // ADJUST=NO: the slave nodes already sit on the master faces (they are copies of its nodes).
      std::snprintf(line, sizeof line,
                    "** %s: the two parts tied (own nodes, CalculiX couples them by equations)\n"
                    "*TIE, NAME=%s, POSITION TOLERANCE=%.6g, ADJUST=NO\n%s, %s\n",
                    c.name.c_str(), c.name.c_str(), c.position_tolerance, slave.c_str(), c.master.c_str());
      cards += line;
      continue;
    }
    std::snprintf(line, sizeof line,
                  "** %s: surface-to-surface penalty contact, %s; CalculiX treats a step with contact as\n"
                  "** nonlinear (increments, contact iterations)\n"
                  "** (%s)\n"
                  "*SURFACE INTERACTION, NAME=%s\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n%.6g\n",
                  c.name.c_str(), c.behaviour.friction > 0 ? "with friction" : "frictionless",
                  c.contact_stiffness_given ? "slope from the job's interfaces contact_stiffness"
                                            : "slope 2.5 E / h for steel, E = 210000 N/mm^2; for another material "
                                              "set the job's interfaces contact_stiffness",
                  c.name.c_str(), c.contact_stiffness);
    cards += line;
    if (c.behaviour.friction > 0) {
      // Stick slope: CalculiX needs one for face-to-face friction; a hundredth of the normal slope.
      std::snprintf(line, sizeof line, "*FRICTION\n%.6g, %.6g\n", c.behaviour.friction, 0.01 * c.contact_stiffness);
      cards += line;
    }
    std::snprintf(line, sizeof line, "*CONTACT PAIR, INTERACTION=%s, TYPE=SURFACE TO SURFACE\n%s, %s\n",
                  c.name.c_str(), c.slave.c_str(), c.master.c_str());
    cards += line;
  }
  return cards;
}

}  // namespace oraclemesh
