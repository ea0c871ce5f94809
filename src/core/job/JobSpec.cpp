#include "job/JobSpec.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>

#include "Error.h"
#include "job/JobJson.h"
#include "mesh/Writers.h"
#include "sizing/Fineness.h"

namespace oraclemesh {
namespace {

using nlohmann::json;
using jobjson::shortDump;

constexpr int64_t kMaxMaterialId = INT32_MAX;
const char* const kMaterialFix = "material ids are positive integer ids (1, 2, ...)";
constexpr int64_t kMaxVertexLimit = 10'000'000'000;
constexpr double kMaxTimeLimit = 365.0 * 24 * 3600;

std::string resolvePath(const std::string& path, const std::string& base) {
  std::filesystem::path p(path);
  if (p.is_absolute() || base.empty()) return p.string();
  return (std::filesystem::path(base) / p).string();
}

double positiveNumber(const json& value, const std::string& where) {
  return jobjson::positiveNumber(value, where, "give a positive value in model units (mm)");
}

void rejectUnknownKeys(const json& object, const std::set<std::string>& known, const std::string& where) {
  for (const auto& [key, value] : object.items())
    if (!known.count(key)) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      const std::string shown = key.size() > 40 ? key.substr(0, 37) + "..." : key;
      throw InputError("unknown key '" + shown + "' in " + where + ": the known keys are " + list);
    }
}

CriteriaSpec parseCriteria(const json& c, const std::string& where) {
  if (!c.is_object()) throw InputError(where + " must be an object of sizes, e.g. {\"cell_size\": 3}");
  rejectUnknownKeys(c, {"cell_size", "cell_radius_edge_ratio", "facet_size", "facet_distance", "facet_angle", "edge_size"}, where);
  CriteriaSpec s;
  auto take = [&](const char* key, std::optional<double>& out) {
    if (c.contains(key)) out = positiveNumber(c[key], where + "." + key);
  };
  take("cell_size", s.cell_size);
  take("cell_radius_edge_ratio", s.cell_radius_edge_ratio);
  take("facet_size", s.facet_size);
  take("facet_distance", s.facet_distance);
  take("facet_angle", s.facet_angle);
  take("edge_size", s.edge_size);
  if (s.facet_angle && *s.facet_angle > 30)
    throw InputError(where + ".facet_angle = " + std::to_string(*s.facet_angle) +
                     " degrees: Delaunay refinement is only guaranteed to end for facet angles up to 30; use 30 or less");
  return s;
}

// Checked before meshing, not when the file is written an hour later.
void checkOutputFolder(const std::string& path, const std::string& where) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw InputError(where + " = '" + path + "': the folder '" + folder.string() +
                     "' does not exist: create it or fix the path (relative paths are taken from the job's folder)");
}

bool isTriangleSurfaceFile(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".stl" || ext == ".obj" || ext == ".off";
}

// {"points": [[x, y, z], ...], "triangles": [[i, j, k], ...]} with 0-based indices; the
// geometry (closed, manifold, oriented) is checked when the surface is built.
void parseSurface(const json& surface, const std::string& label, const std::string& path, InputSpec& s) {
  const std::string form = ": 'surface' must be {\"points\": [[x, y, z], ...], \"triangles\": [[i, j, k], ...]} "
                           "with point indices counted from 0";
  if (!surface.is_object() || !surface.contains("points") || !surface.contains("triangles") ||
      !surface["points"].is_array() || !surface["triangles"].is_array())
    throw InputError(label + form);
  rejectUnknownKeys(surface, {"points", "triangles"}, label + " surface");
  s.kind = InputSpec::Kind::Surface;
  const json& points = surface["points"];
  s.surface_points.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const json& p = points[i];
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
      throw InputError(label + ": " + path + ".points[" + std::to_string(i) + "] = " + shortDump(p) + " is not [x, y, z]" +
                       form);
    s.surface_points.push_back({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
  }
  const json& triangles = surface["triangles"];
  s.surface_triangles.reserve(triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i) {
    const json& t = triangles[i];
    // Indices beyond int64 would wrap; the ones beyond the points are named when the surface is built.
    auto index = [](const json& v) {
      return v.is_number_unsigned() ? v.get<uint64_t>() <= uint64_t(INT64_MAX) : v.is_number_integer();
    };
    if (!t.is_array() || t.size() != 3 || !index(t[0]) || !index(t[1]) || !index(t[2]))
      throw InputError(label + ": " + path + ".triangles[" + std::to_string(i) + "] = " + shortDump(t) +
                       " is not three point indices" + form);
    s.surface_triangles.push_back({t[0].get<int64_t>(), t[1].get<int64_t>(), t[2].get<int64_t>()});
  }
}

// A positive integer written as a JSON object key ("1"); 0 when it is not one.
int positiveIntegerKey(const std::string& key) {
  try {
    size_t used = 0;
    const int id = std::stoi(key, &used);
    return used == key.size() && id > 0 ? id : 0;
  } catch (...) {
    return 0;
  }
}

InputSpec parseInput(const json& in, size_t index, const std::string& base) {
  const std::string where = "inputs[" + std::to_string(index) + "]";
  if (!in.is_object()) throw InputError(where + " must be an object like {\"name\": \"pin\", \"file\": \"pin.step\", \"material\": 1}");
  rejectUnknownKeys(in, {"name", "file", "brep", "sphere", "surface", "image", "role", "material", "materials", "solids"},
                    where);
  InputSpec s;
  s.name = in.contains("name") ? jobjson::string(in["name"], where + ".name", "give the input a name, e.g. \"pin\"")
                               : "input " + std::to_string(index + 1);
  const std::string label = "input '" + s.name + "'";
  const std::string role =
      in.contains("role") ? jobjson::string(in["role"], where + ".role", "use \"material\" or \"cut\"") : "material";
  const int kinds = int(in.contains("file")) + int(in.contains("brep")) + int(in.contains("sphere")) +
                    int(in.contains("surface")) + int(in.contains("image"));
  if (kinds != 1)
    throw InputError(label + " must have exactly one of 'file', 'brep', 'sphere', 'surface' or 'image' (it has " +
                     std::to_string(kinds) + ")");
  if (in.contains("file")) {
    if (!in["file"].is_string() || in["file"].get<std::string>().empty())
      throw InputError(label + ": 'file' must be a path to a STEP, IGES, BREP, STL, OBJ or OFF file");
    s.kind = InputSpec::Kind::File;
    s.file = resolvePath(in["file"].get<std::string>(), base);
  } else if (in.contains("brep")) {
    if (!in["brep"].is_string() || in["brep"].get<std::string>().empty())
      throw InputError(label + ": 'brep' must be non-empty BREP text (FreeCAD: Shape.exportBrepToString())");
    s.kind = InputSpec::Kind::BrepText;
    s.brep_text = in["brep"].get<std::string>();
  } else if (in.contains("surface")) {
    parseSurface(in["surface"], label, where + ".surface", s);
  } else if (in.contains("image")) {
    if (!in["image"].is_string() || in["image"].get<std::string>().empty())
      throw InputError(label + ": 'image' must be the path of a NRRD label image (.nrrd/.nhdr); from Python it may also "
                       "be {\"labels\": array, \"spacing\": [sx, sy, sz], \"origin\": [x, y, z]}");
    s.kind = InputSpec::Kind::Image;
    s.image = resolvePath(in["image"].get<std::string>(), base);
    if (in.contains("material"))
      throw InputError(label + " is an image: give 'materials' (label -> material, e.g. {\"1\": 2, \"2\": 4}) instead of 'material'");
    if (role != "material")
      throw InputError(label + ": image inputs can only have role 'material'; cut with another input instead");
    const json& m = in.contains("materials") ? in["materials"] : json();
    if (!m.is_object() || m.empty())
      throw InputError(label + " is an image and needs 'materials', a map from its labels to material ids, "
                       "e.g. {\"1\": 2, \"2\": 4} (label 0 is background)");
    for (const auto& [key, value] : m.items()) {
      const int imageLabel = positiveIntegerKey(key);
      if (imageLabel <= 0)
        throw InputError(label + ": 'materials' key '" + key + "' is not an image label: use positive integer labels as keys "
                         "(label 0 is background and is never meshed)");
      if (!value.is_number_unsigned() || value.get<uint64_t>() == 0 || value.get<uint64_t>() > uint64_t(kMaxMaterialId))
        throw InputError(label + ": 'materials' (" + where + ".materials) maps label " + key + " to " + shortDump(value) +
                         ": material ids must be positive integers (1, 2, ...)");
      s.image_materials[imageLabel] = value.get<int>();
    }
    return s;
  } else {
    const json& sp = in["sphere"];
    if (!sp.is_object() || !sp.contains("center") || !sp.contains("radius") || !sp["center"].is_array() || sp["center"].size() != 3)
      throw InputError(label + ": 'sphere' must be {\"center\": [x, y, z], \"radius\": r}");
    s.kind = InputSpec::Kind::Sphere;
    for (int i = 0; i < 3; ++i)
      s.center[i] = jobjson::number(sp["center"][i], where + ".sphere.center[" + std::to_string(i) + "]",
                                    "the centre of " + label + " must be three finite numbers");
    s.radius = positiveNumber(sp["radius"], where + ".sphere.radius (" + label + ")");
  }
  const bool brep = s.kind == InputSpec::Kind::BrepText || (s.kind == InputSpec::Kind::File && !isTriangleSurfaceFile(s.file));
  if (in.contains("solids")) {
    if (!brep)
      throw InputError(label + ": 'solids' applies to STEP, IGES and BREP inputs only (this input is one surface): "
                       "remove it");
    const json& g = in["solids"];
    if (g != "separate" && g != "together")
      throw InputError(label + ": 'solids' must be \"separate\" (one input per solid, in file order) or "
                       "\"together\" (all solids as one input), got " + shortDump(g));
    s.solids_together = g == "together";
  }
  if (role == "material") {
    s.role = Role::Material;
    s.material = in.contains("material")
                     ? static_cast<int>(jobjson::integer(in["material"], where + ".material (" + label + ")", 1,
                                                         kMaxMaterialId, kMaterialFix))
                     : static_cast<int>(std::min<size_t>(index + 1, kMaxMaterialId));
    if (in.contains("materials")) {
      if (in.contains("material"))
        throw InputError(label + " has both 'material' and 'materials': give one material for all solids, or a list "
                         "with one per solid");
      if (!brep || s.solids_together)
        throw InputError(label + ": 'materials' belongs to STEP, IGES or BREP inputs with \"solids\": \"separate\" (a list, "
                         "one material per solid) and to 'image' inputs (a map from labels to materials); use 'material' "
                         "for this input");
      const json& list = in["materials"];
      if (!list.is_array() || list.empty())
        throw InputError(label + ": 'materials' must be a list of material ids, one per solid in file order, e.g. [1, 2, 2]");
      for (size_t k = 0; k < list.size(); ++k)
        s.solid_materials.push_back(static_cast<int>(jobjson::integer(
            list[k], where + ".materials[" + std::to_string(k) + "] (" + label + ")", 1, kMaxMaterialId, kMaterialFix)));
    }
  } else if (role == "cut") {
    s.role = Role::Cut;
    if (in.contains("material") || in.contains("materials"))
      throw InputError(label + " has role 'cut' and a material: a cut region removes material, remove its 'material' key");
  } else {
    throw InputError(label + ": role '" + role + "' is unknown: use 'material' or 'cut'");
  }
  return s;
}

const char* const kInterfaceKinds = "\"bonded\" (shared nodes), \"tied\", \"contact\" or \"separate\"";

InterfaceKind parseInterfaceKind(const json& value, const std::string& where) {
  for (InterfaceKind kind : {InterfaceKind::Bonded, InterfaceKind::Tied, InterfaceKind::Contact, InterfaceKind::Separate})
    if (value == interfaceKindName(kind)) return kind;
  throw InputError(where + " = " + shortDump(value) + " is not an interface kind: use " + kInterfaceKinds);
}

// The contact slope at `where` (interfaces.contact_stiffness or a pair's).
double parseContactStiffness(const json& value, const std::string& where) {
  const std::string fix = "give the contact pressure per unit of overclosure (force / length^3 in the model's units, "
                          "e.g. N/mm^3), > 0";
  return jobjson::positiveNumber(value, where, fix);
}

// {"default": "bonded", "contact_stiffness": 1e4,
//  "pairs": [{"between": ["top", "bottom"], "kind": "contact", "friction": 0.2, "contact_stiffness": 5e3}]}
InterfacesSpec parseInterfaces(const json& value) {
  const std::string form = ": give {\"default\": \"bonded\", \"pairs\": [{\"between\": [\"top\", \"bottom\"], "
                           "\"kind\": \"contact\"}]} with parts named as in report.interfaces";
  if (!value.is_object()) throw InputError("'interfaces' must be an object" + form);
  rejectUnknownKeys(value, {"default", "contact_stiffness", "pairs"}, "interfaces");
  InterfacesSpec spec;
  if (value.contains("default")) spec.default_kind = parseInterfaceKind(value["default"], "interfaces.default");
  if (value.contains("contact_stiffness"))
    spec.default_contact_stiffness = parseContactStiffness(value["contact_stiffness"], "interfaces.contact_stiffness");
  if (!value.contains("pairs")) return spec;
  const json& pairs = value["pairs"];
  if (!pairs.is_array()) throw InputError("interfaces.pairs must be a list" + form);
  std::map<std::set<std::string>, size_t> seen;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const std::string where = "interfaces.pairs[" + std::to_string(i) + "]";
    const json& p = pairs[i];
    if (!p.is_object()) throw InputError(where + " must be an object like {\"between\": [\"top\", \"bottom\"], \"kind\": \"tied\"}");
    rejectUnknownKeys(p, {"between", "kind", "friction", "contact_stiffness", "master"}, where);
    InterfacePairSpec pair;
    const json& between = p.contains("between") ? p["between"] : json();
    if (!between.is_array() || between.size() != 2 || !between[0].is_string() || !between[1].is_string())
      throw InputError(where + ".between must be the names of two parts, e.g. [\"top\", \"bottom\"] (as in "
                       "report.interfaces[i].parts), got " + shortDump(between));
    pair.between = {between[0].get<std::string>(), between[1].get<std::string>()};
    if (pair.between[0] == pair.between[1])
      throw InputError(where + ".between names part '" + pair.between[0] + "' twice: an interface is between two different parts");
    const std::set<std::string> key(pair.between.begin(), pair.between.end());
    if (const auto it = seen.find(key); it != seen.end())
      throw InputError(where + " repeats the pair '" + pair.between[0] + "', '" + pair.between[1] +
                       "' of interfaces.pairs[" + std::to_string(it->second) + "]: give each pair once");
    seen[key] = i;
    if (!p.contains("kind")) throw InputError(where + " has no 'kind': use " + kInterfaceKinds);
    pair.behaviour.kind = parseInterfaceKind(p["kind"], where + ".kind");
    if (p.contains("friction")) {
      if (pair.behaviour.kind != InterfaceKind::Contact)
        throw InputError(where + ".friction belongs to kind \"contact\" only (this pair is \"" +
                         interfaceKindName(pair.behaviour.kind) + "\"): remove it or make the pair a contact");
      pair.behaviour.friction = jobjson::number(p["friction"], where + ".friction",
                                                "give a Coulomb friction coefficient >= 0 (0 = frictionless)");
      if (pair.behaviour.friction < 0)
        throw InputError(where + ".friction = " + shortDump(p["friction"]) +
                         " is negative: give a Coulomb friction coefficient >= 0 (0 = frictionless)");
    }
    if (p.contains("contact_stiffness")) {
      if (pair.behaviour.kind != InterfaceKind::Contact)
        throw InputError(where + ".contact_stiffness belongs to kind \"contact\" only (this pair is \"" +
                         interfaceKindName(pair.behaviour.kind) + "\"): remove it or make the pair a contact");
      pair.behaviour.contact_stiffness = parseContactStiffness(p["contact_stiffness"], where + ".contact_stiffness");
    }
    if (p.contains("master")) {
      if (pair.behaviour.kind != InterfaceKind::Tied && pair.behaviour.kind != InterfaceKind::Contact)
        throw InputError(where + ".master applies to kinds \"tied\" and \"contact\" only: remove it");
      pair.master = jobjson::string(p["master"], where + ".master", "give one of the two parts of 'between'");
      if (pair.master != pair.between[0] && pair.master != pair.between[1])
        throw InputError(where + ".master = '" + pair.master + "' is not one of the pair's parts '" +
                         pair.between[0] + "', '" + pair.between[1] + "'");
    }
    spec.pairs.push_back(pair);
  }
  return spec;
}

}  // namespace

std::vector<int> InputSpec::materials() const {
  if (kind == Kind::Image) {
    std::vector<int> ids;
    for (const auto& [imageLabel, material] : image_materials) ids.push_back(material);
    return ids;
  }
  if (role != Role::Material) return {};
  if (!solid_materials.empty()) return solid_materials;
  return {material};
}

JobSpec JobSpec::fromJsonText(const std::string& text, const std::string& baseDirectory) {
  return fromJson(jobjson::parse(text), baseDirectory);
}

static Point3 parsePoint(const json& p, const std::string& where) {
  Point3 q{};
  bool ok = p.is_array() && p.size() == 3;
  for (int c = 0; ok && c < 3; ++c) {
    ok = p[c].is_number() && std::isfinite(p[c].get<double>());
    if (ok) q[c] = p[c].get<double>();
  }
  if (!ok) throw InputError(where + " = " + shortDump(p) + " is not [x, y, z] with finite numbers");
  return q;
}

// features.polylines: [[[x, y, z], [x, y, z], ...], ...] or [{"points": [...], "brep": "..."}, ...].
static std::vector<std::vector<Point3>> parsePolylines(const json& value, std::vector<std::string>& curves) {
  const std::string usage =
      ": give a list of polylines, each a list of at least two [x, y, z] points in model units "
      "(or {\"points\": [...]})";
  if (!value.is_array()) throw InputError("features.polylines" + usage);
  std::vector<std::vector<Point3>> polylines;
  for (size_t i = 0; i < value.size(); ++i) {
    const std::string where = "features.polylines[" + std::to_string(i) + "]";
    const json& item = value[i].is_object() && value[i].contains("points") ? value[i]["points"] : value[i];
    if (value[i].is_object()) rejectUnknownKeys(value[i], {"points", "brep"}, where);
    const bool hasCurve = value[i].is_object() && value[i].contains("brep");
    if (hasCurve && !value[i]["brep"].is_string())
      throw InputError(where + ".brep must be BREP text of one edge (Part.Edge.exportBrepToString())");
    curves.push_back(hasCurve ? value[i]["brep"].get<std::string>() : std::string());
    if (!item.is_array() || item.size() < 2) throw InputError(where + usage);
    std::vector<Point3> points;
    for (size_t k = 0; k < item.size(); ++k) {
      const json& p = item[k];
      const Point3 q = parsePoint(p, where + " point " + std::to_string(k));
      if (!points.empty() && q == points.back())
        throw InputError(where + " repeats point " + std::to_string(k) + " " + shortDump(p) + ": remove the duplicate");
      points.push_back(q);
    }
    polylines.push_back(std::move(points));
  }
  return polylines;
}

const char* engineName(Engine engine) { return engine == Engine::Thesis ? "thesis" : "cgal"; }

const char* materialAssignmentName(MaterialAssignment assignment) {
  return assignment == MaterialAssignment::Barycenter ? "barycenter" : "circumcenter";
}

JobSpec JobSpec::fromJson(const json& job, const std::string& base) {
  if (!job.is_object()) throw InputError("the job must be a JSON object with at least an 'inputs' list");
  rejectUnknownKeys(job, {"inputs", "criteria", "features", "engine", "material_assignment", "initial_points", "optimize",
                          "element_order", "limits", "seed", "checks", "interfaces", "output",
                          "contact_tolerance", "cad_uncertainty"},
                    "the job");
  JobSpec spec;
  if (!job.contains("inputs") || !job["inputs"].is_array() || job["inputs"].empty())
    throw InputError("the job has no inputs: add at least one solid to 'inputs' (highest priority first)");
  for (size_t i = 0; i < job["inputs"].size(); ++i) spec.inputs.push_back(parseInput(job["inputs"][i], i, base));
  if (std::none_of(spec.inputs.begin(), spec.inputs.end(), [](const InputSpec& s) { return s.role == Role::Material; }))
    throw InputError("all inputs have role 'cut', so nothing is left to mesh: give at least one input role 'material'");

  if (job.contains("criteria")) {
    const json& c = job["criteria"];
    if (!c.is_object()) throw InputError("'criteria' must be an object with 'default' and/or 'materials'");
    rejectUnknownKeys(c, {"default", "materials", "fineness"}, "criteria");
    if (c.contains("fineness")) {
      const json& f = c["fineness"];
      if (!f.is_string() || (f.get<std::string>() != "off" && !findFineness(f.get<std::string>()))) {
        std::string names;
        for (const FinenessPreset& p : kFinenessPresets) names += std::string(p.name) + ", ";
        throw InputError("criteria.fineness = " + shortDump(f) + " is not a fineness: use one of " + names + "or \"off\"");
      }
      spec.fineness = f.get<std::string>();
    }
    if (c.contains("default")) spec.default_criteria = parseCriteria(c["default"], "criteria.default");
    if (c.contains("materials")) {
      if (!c["materials"].is_object()) throw InputError("criteria.materials must map material ids to criteria, e.g. {\"1\": {\"cell_size\": 1}}");
      for (const auto& [key, value] : c["materials"].items()) {
        const int id = positiveIntegerKey(key);
        if (id <= 0) throw InputError("criteria.materials key '" + key + "' is not a material id: use positive integers as keys");
        spec.material_criteria[id] = parseCriteria(value, "criteria.materials." + key);
      }
    }
  }

  if (job.contains("features")) {
    const json& f = job["features"];
    if (f.is_boolean()) {
      spec.features = f.get<bool>();
    } else if (f.is_object()) {
      rejectUnknownKeys(f, {"sharp_angle_deg", "junctions", "polylines", "planar_faces"}, "features");
      if (f.contains("sharp_angle_deg")) {
        // 0 = no sharp B-rep edges (junctions and polylines as asked).
        const json& angle = f["sharp_angle_deg"];
        spec.sharp_angle_deg = angle.is_number() ? angle.get<double>() : -1;
        if (!(spec.sharp_angle_deg >= 0 && spec.sharp_angle_deg < 180))
          throw InputError("features.sharp_angle_deg = " + shortDump(angle) +
                           " must be a number from 0 (no sharp edges) to below 180 degrees");
      }
      if (f.contains("junctions")) spec.junctions = jobjson::boolean(f["junctions"], "features.junctions");
      if (f.contains("polylines")) spec.user_polylines = parsePolylines(f["polylines"], spec.user_polyline_curves);
      if (f.contains("planar_faces")) spec.planar_faces = jobjson::boolean(f["planar_faces"], "features.planar_faces");
    } else {
      throw InputError("'features' must be false or an object like {\"sharp_angle_deg\": 30}");
    }
  }

  if (job.contains("engine")) {
    const std::string engine = job["engine"].is_string() ? job["engine"].get<std::string>() : "";
    if (engine == engineName(Engine::Thesis))
      spec.engine = Engine::Thesis;
    else if (engine == engineName(Engine::Cgal))
      spec.engine = Engine::Cgal;
    else
      throw InputError("engine must be 'cgal' (Mesh_3) or 'thesis' (Rule Set T), got " + shortDump(job["engine"]));
  }
  if (spec.planar_faces) {
    if (spec.engine != Engine::Thesis)
      throw InputError("features.planar_faces needs engine \"thesis\": the 'cgal' engine (Mesh_3) cannot keep planar "
                       "faces flat; set \"engine\": \"thesis\" or remove features.planar_faces");
    // The recovery is well posed only where the faces' borders are constrained segments.
    if (!(spec.sharp_angle_deg > 0) || !spec.junctions)
      throw InputError("features.planar_faces needs sharp edges and junctions (features.sharp_angle_deg > 0 and "
                       "features.junctions true): the planar faces' borders must be constrained segments");
  }
  if (job.contains("material_assignment")) {
    const json& m = job["material_assignment"];
    if (m == materialAssignmentName(MaterialAssignment::Circumcenter))
      spec.material_assignment = MaterialAssignment::Circumcenter;
    else if (m == materialAssignmentName(MaterialAssignment::Barycenter))
      spec.material_assignment = MaterialAssignment::Barycenter;
    else
      throw InputError("material_assignment must be \"circumcenter\" or \"barycenter\", got " + shortDump(m));
    if (spec.engine != Engine::Thesis && spec.material_assignment != MaterialAssignment::Circumcenter)
      throw InputError("material_assignment: the 'cgal' engine assigns materials by circumcentre only: use "
                       "\"circumcenter\" or engine 'thesis'");
  }
  if (job.contains("initial_points") && !job["initial_points"].empty()) {
    if (spec.engine != Engine::Thesis)
      throw InputError("initial_points are not supported by the 'cgal' engine: remove them or use engine 'thesis'");
    const json& list = job["initial_points"];
    if (!list.is_array()) throw InputError("initial_points must be a list of [x, y, z] points in model units");
    for (size_t k = 0; k < list.size(); ++k) {
      spec.initial_points.push_back(parsePoint(list[k], "initial_points[" + std::to_string(k) + "]"));
    }
  }

  if (job.contains("element_order")) {
    const json& o = job["element_order"];
    // Compared as JSON values: 4294967297 must not pass as 1 through a 32-bit conversion.
    if (!o.is_number_integer() || (o != 1 && o != 2))
      throw InputError("element_order must be 1 (tet4) or 2 (tet10), got " + shortDump(o));
    spec.element_order = o == 1 ? 1 : 2;
  }
  if (job.contains("optimize")) {
    const json& o = job["optimize"];
    if (o.is_boolean()) {
      spec.perturb = spec.exude = o.get<bool>();
    } else if (o.is_object()) {
      rejectUnknownKeys(o, {"perturb", "exude", "improve", "time_limit", "sliver_bound"}, "optimize");
      if (o.contains("improve")) spec.improve = jobjson::boolean(o["improve"], "optimize.improve");
      if (o.contains("perturb")) spec.perturb = jobjson::boolean(o["perturb"], "optimize.perturb");
      if (o.contains("exude")) spec.exude = jobjson::boolean(o["exude"], "optimize.exude");
      if (o.contains("time_limit")) spec.optimize_time_limit = positiveNumber(o["time_limit"], "optimize.time_limit");
      if (o.contains("sliver_bound")) {
        spec.sliver_bound = positiveNumber(o["sliver_bound"], "optimize.sliver_bound");
        if (spec.sliver_bound >= 70)
          throw InputError("optimize.sliver_bound must be below 70 degrees (a regular tetrahedron has 70.5)");
      }
    } else {
      throw InputError("'optimize' must be true/false or {\"perturb\": true, \"exude\": true, \"sliver_bound\": 10}");
    }
  }
  if (job.contains("limits")) {
    const json& l = job["limits"];
    if (!l.is_object()) throw InputError("'limits' must be an object like {\"max_vertices\": 5000000, \"time_limit\": 3600}");
    rejectUnknownKeys(l, {"max_vertices", "time_limit"}, "limits");
    if (l.contains("max_vertices"))
      spec.max_vertices = jobjson::integer(l["max_vertices"], "limits.max_vertices", 1, kMaxVertexLimit,
                                           "give the largest vertex count to accept (a mesh of 1e10 vertices "
                                           "would need terabytes of memory)");
    if (l.contains("time_limit")) {
      spec.time_limit = positiveNumber(l["time_limit"], "limits.time_limit");
      if (spec.time_limit > kMaxTimeLimit)
        throw InputError("limits.time_limit = " + shortDump(l["time_limit"]) + " s is more than a year: give seconds, "
                         "at most " + std::to_string(int64_t(kMaxTimeLimit)));
    }
  }
  if (job.contains("seed"))
    spec.seed = static_cast<unsigned>(jobjson::integer(job["seed"], "seed", 0, UINT32_MAX,
                                                       "the seed is a non-negative 32-bit integer"));
  if (job.contains("contact_tolerance")) {
    const double tolerance =
        jobjson::number(job["contact_tolerance"], "contact_tolerance",
                        "give a distance in model units (mm) at or above 0: parts closer than it are bonded");
    if (tolerance < 0)
      throw InputError("contact_tolerance = " + shortDump(job["contact_tolerance"]) +
                       " is negative: give a distance in model units (mm) at or above 0 (parts closer than it are "
                       "bonded), or leave it out for the CAD's own tolerance");
    spec.contact_tolerance = tolerance;
  }
  if (job.contains("cad_uncertainty")) {
    spec.cad_uncertainty = jobjson::number(job["cad_uncertainty"], "cad_uncertainty",
                                           "give the CAD file's declared uncertainty in model units (mm), at or above 0");
    if (spec.cad_uncertainty < 0)
      throw InputError("cad_uncertainty = " + shortDump(job["cad_uncertainty"]) +
                       " is negative: give the CAD file's declared uncertainty in model units (mm), at or above 0");
  }
  if (job.contains("checks")) {
    const json& c = job["checks"];
    if (!c.is_string() || (c != "warn" && c != "error"))
      throw InputError("'checks' must be \"warn\" (a mesh that fails its volume or connectivity check is "
                       "written with warnings) or \"error\" (it is refused)");
    spec.checks = c == "error" ? MeshCheckMode::Error : MeshCheckMode::Warn;
  }
  if (job.contains("interfaces")) spec.interfaces = parseInterfaces(job["interfaces"]);
  if (job.contains("output")) {
    const json& o = job["output"];
    if (!o.is_object()) throw InputError("'output' must be like {\"files\": [\"mesh.vtu\", \"mesh.inp\"], \"report\": \"report.json\"}");
    rejectUnknownKeys(o, {"files", "report"}, "output");
    if (o.contains("files")) {
      if (!o["files"].is_array()) throw InputError("output.files must be a list of paths (.vtu, .inp)");
      for (size_t k = 0; k < o["files"].size(); ++k) {
        const std::string where = "output.files[" + std::to_string(k) + "]";
        const std::string path = resolvePath(jobjson::string(o["files"][k], where, "give a path (.vtu, .inp)"), base);
        const std::string problem = meshFileFormatProblem(path);
        if (!problem.empty()) throw InputError(where + " = '" + path + "': " + problem);
        checkOutputFolder(path, where);
        spec.output_files.push_back(path);
      }
    }
    if (o.contains("report")) {
      spec.report_file = resolvePath(jobjson::string(o["report"], "output.report", "give a path (report.json)"), base);
      checkOutputFolder(spec.report_file, "output.report");
    }
  }
  return spec;
}

}  // namespace oraclemesh
