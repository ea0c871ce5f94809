#include "job/ResolvedCriteria.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <set>
#include <string>

#include "Error.h"
#include "sizing/DiscreteSurface.h"
#include "sizing/GeometrySizes.h"

namespace oraclemesh {

namespace {

constexpr double kSmallestSizeOfDiagonal = 1e-6;
// The face samples lie on every corner of every tessellation triangle, a curvature and a
// thickness sample each: those the others give within 10 % are dropped (the field is then at
// most 10 % above the one of all samples, sizing/SampleThinning.h).
constexpr double kSampleThinning = 0.1;
// Gap sizes where the job gives its sizes (criteria.fineness "off") grade as at "coarse".
constexpr double kGapGradingAtGivenSizes = 0.5;

MaterialCriteria resolve(const CriteriaSpec& spec, const MaterialCriteria& fallback) {
  MaterialCriteria c = fallback;
  if (spec.cell_size) c.cell_size = *spec.cell_size;
  if (spec.cell_radius_edge_ratio) c.cell_radius_edge_ratio = *spec.cell_radius_edge_ratio;
  if (spec.facet_size) c.facet_size = *spec.facet_size;
  if (spec.facet_distance) c.facet_distance = *spec.facet_distance;
  if (spec.facet_angle) c.facet_angle = *spec.facet_angle;
  if (spec.edge_size) c.edge_size = *spec.edge_size;
  return c;
}

// A count for messages: "1.2e+19", never a wrapped 64-bit integer.
std::string roughCount(double n) {
  if (!std::isfinite(n)) return "more than 1e308";
  char text[32];
  std::snprintf(text, sizeof text, n < 1e15 ? "%.0f" : "%.2g", n);
  return text;
}

// A length far below the model's size would make curve sampling or refinement allocate
// without bound before any vertex count is checked: refused naming the key it came from.
void checkSizesAgainstModel(const JobSpec& job, int material, const MaterialCriteria& c, double diagonal) {
  if (!(diagonal > 0) || !std::isfinite(diagonal)) return;  // the engines refuse an empty model
  const auto found = job.material_criteria.find(material);
  const CriteriaSpec none;
  const CriteriaSpec& own = found == job.material_criteria.end() ? none : found->second;
  const CriteriaSpec& fallback = job.default_criteria;
  struct Size {
    const char* key;
    double value;
    bool ownValue, defaultValue;  // where the user gave it, if anywhere
  };
  const Size sizes[] = {
      {"cell_size", c.cell_size, own.cell_size.has_value(), fallback.cell_size.has_value()},
      {"facet_size", c.facet_size, own.facet_size.has_value(), fallback.facet_size.has_value()},
      {"facet_distance", c.facet_distance, own.facet_distance.has_value(), fallback.facet_distance.has_value()},
      {"edge_size", c.edge_size, own.edge_size.has_value(), fallback.edge_size.has_value()}};
  for (const Size& size : sizes) {
    // Derived sizes are within 1/20 of given ones: bounded when those are.
    if (size.value >= kSmallestSizeOfDiagonal * diagonal || !(size.ownValue || size.defaultValue)) continue;
    const std::string key = size.ownValue ? "criteria.materials." + std::to_string(material) + "." + size.key
                                          : std::string("criteria.default.") + size.key;
    char text[200];
    std::snprintf(text, sizeof text,
                  " = %g is less than a millionth of the model's size (bounding-box diagonal %g): give sizes in model "
                  "units (FreeCAD works in mm), at least %g",
                  size.value, diagonal, kSmallestSizeOfDiagonal * diagonal);
    throw InputError(key + text);
  }
}

}  // namespace

// Unset sizes follow the model: a user who gives nothing gets a coarse but sound mesh.
CriteriaTable resolveCriteria(const JobSpec& job, double diagonal) {
  CriteriaTable table;
  MaterialCriteria base;
  const CriteriaSpec& d = job.default_criteria;
  base.cell_size = d.cell_size.value_or(diagonal / 15);
  base.facet_size = d.facet_size.value_or(base.cell_size);
  base.facet_distance = d.facet_distance.value_or(base.facet_size / 10);
  base.cell_radius_edge_ratio = d.cell_radius_edge_ratio.value_or(2);
  base.facet_angle = d.facet_angle.value_or(25);
  base.edge_size = d.edge_size.value_or(base.facet_size / 2);
  const bool sized = jobFineness(job) != nullptr;
  base.from_field = {sized && !d.cell_size, sized && !d.facet_size, sized && !d.facet_distance, sized && !d.edge_size};
  table.defaults = base;

  std::set<int> materials;
  for (const InputSpec& in : job.inputs)
    for (int id : in.materials()) materials.insert(id);
  for (const auto& [id, spec] : job.material_criteria)
    if (!materials.count(id))
      throw InputError("criteria.materials names material " + std::to_string(id) +
                       " but no input has that material: fix the id or remove the entry");
  for (int id : materials) {
    auto it = job.material_criteria.find(id);
    table.per_material[id] = it == job.material_criteria.end() ? base : resolve(it->second, base);
    if (it != job.material_criteria.end()) {
      MaterialCriteria::FromField& use = table.per_material[id].from_field;
      use.cell_size = use.cell_size && !it->second.cell_size;
      use.facet_size = use.facet_size && !it->second.facet_size;
      use.facet_distance = use.facet_distance && !it->second.facet_distance;
      use.edge_size = use.edge_size && !it->second.edge_size;
    }
    checkSizesAgainstModel(job, id, table.per_material[id], diagonal);
  }
  return table;
}

const FinenessPreset* jobFineness(const JobSpec& job) {
  return findFineness(job.fineness.value_or(kDefaultFineness));  // "off" is no preset
}

std::vector<PartGap> attachSizeField(CriteriaTable& table, const JobSpec& job, const HierarchicalOracle& oracle,
                                     double contactTolerance, const RunControl& control) {
  const FinenessPreset* fineness = jobFineness(job);
  const auto hasSurface = [](const OracleEntry& e) {
    return e.source->brepTopology() != nullptr || hasDiscreteSurface(*e.source);
  };
  if (!fineness && std::count_if(oracle.entries().begin(), oracle.entries().end(), hasSurface) < 2) return {};
  const double sharpAngle = job.features ? job.sharp_angle_deg : 0;
  // Gaps in every material: the largest cell size any has.
  const double cap = table.strictest(&MaterialCriteria::cell_size, false);
  const double grading = fineness ? fineness->grading : kGapGradingAtGivenSizes;
  GeometrySizes sizes = geometrySizes(oracle, fineness, kSizesPerGap, sharpAngle, cap, contactTolerance,
                                      static_cast<double>(job.max_vertices), control);
  const std::string preset = "criteria.fineness " + std::string(fineness ? fineness->name : "off");
  if (!(sizes.surface_vertices <= static_cast<double>(job.max_vertices))) {
    const std::string tooMany = " would give about " + roughCount(sizes.surface_vertices) +
                                " vertices on the surfaces alone, more than limits.max_vertices = " +
                                std::to_string(job.max_vertices);
    const Point3& at = sizes.smallest.point;
    char where[200];
    // The narrowest gap of the entry asking the most asks its smallest size.
    const auto gap = std::find_if(sizes.gaps.begin(), sizes.gaps.end(), [&](const PartGap& g) {
      return g.entry == sizes.largest_entry || g.other == sizes.largest_entry;
    });
    if (sizes.smallest.reason == SizeReason::Gap && gap != sizes.gaps.end()) {
      std::snprintf(where, sizeof where, "%g wide at (%g, %g, %g) asks for size %g", gap->width, gap->at[0],
                    gap->at[1], gap->at[2], gap->width / kSizesPerGap);
      char bond[160];
      std::snprintf(bond, sizeof bond, "contact_tolerance above %g (now %g)", gap->width, contactTolerance);
      throw InputError("the gap between inputs '" + oracle.entries()[gap->entry].source->name() + "' and '" +
                       oracle.entries()[gap->other].source->name() + "' is " + where + " (" + preset +
                       "), and the sizes the geometry asks for" + tooMany +
                       ": if the two parts are meant to touch, set " + bond +
                       " to bond them; else raise limits.max_vertices (the mesh keeps parts that do not touch "
                       "apart at every size)");
    }
    if (!(sizes.smallest.size < cap)) {
      // Nothing on that input asks for less than the cap: the sizes given are what is too small.
      std::snprintf(where, sizeof where, "%g", cap);
      throw InputError("the sizes given (cell_size " + std::string(where) + " on input '" +
                       oracle.entries()[sizes.largest_entry].source->name() + "')" + tooMany +
                       ": raise cell_size and facet_size (check the model units: FreeCAD works in mm) or raise "
                       "limits.max_vertices");
    }
    std::snprintf(where, sizeof where, "%g at (%g, %g, %g), from %s", sizes.smallest.size, at[0], at[1], at[2],
                  sizeReasonName(sizes.smallest.reason));
    throw InputError("the sizes the geometry asks for (" + preset + ", smallest size on input '" +
                     oracle.entries()[sizes.largest_entry].source->name() + "' " + where + ")" + tooMany +
                     ": choose a coarser criteria.fineness, give that input its own sizes, or raise limits.max_vertices");
  }
  const double floor = kSmallestSizeOfDiagonal * oracle.diagonal();
  if (fineness) {
    std::vector<SizeSample> cellSamples = sizes.samples;
    for (SizeSample& s : cellSamples)
      if (s.reason != SizeReason::Thickness) s.size *= kCellSizePerSurfaceSize;
    table.field = std::make_shared<const SizeField>(std::move(sizes.samples), grading, cap, floor, kSampleThinning);
    table.cell_field = std::make_shared<const SizeField>(std::move(cellSamples), grading, cap, floor, kSampleThinning);
  }
  if (!sizes.bonded_wedges.empty())
    table.bonded_wedges = std::make_shared<const BondedWedges>(std::move(sizes.bonded_wedges));
  if (!sizes.gap_samples.empty())
    table.gap_field =
        std::make_shared<const SizeField>(std::move(sizes.gap_samples), grading, cap, floor, kSampleThinning);
  return std::move(sizes.gaps);
}

// Refuse up front what would blow the vertex limit: a tet whose circumradius is near the
// bound has about 0.11 r^3 of volume and a mesh has about six tets per vertex.
void checkExpectedSize(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& table) {
  const std::vector<OracleEntry>& entries = oracle.entries();
  double expected = 0;
  for (const OracleEntry& e : entries) {
    if (e.role != Role::Material) continue;
    const double r = table.of(e.material).cell_size;
    expected += e.source->volume() / (0.66 * r * r * r);
  }
  if (!(expected <= static_cast<double>(job.max_vertices)))
    throw InputError("the sizes asked for would give about " + roughCount(expected) +
                     " vertices, more than limits.max_vertices = " + std::to_string(job.max_vertices) +
                     ": raise cell_size (check the model units: FreeCAD works in mm) or raise limits.max_vertices");
}

}  // namespace oraclemesh
