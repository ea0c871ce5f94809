#include "job/ResolvedCriteria.h"

#include <cstdint>
#include <set>
#include <string>

#include "Error.h"

namespace oraclemesh {

namespace {

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
  }
  return table;
}

// Refuse up front what would blow the vertex limit: a tet whose circumradius is near the
// bound has about 0.11 r^3 of volume and a mesh has about six tets per vertex.
void checkExpectedSize(const JobSpec& job, const std::vector<OracleEntry>& entries, const CriteriaTable& table) {
  double expected = 0;
  for (const OracleEntry& e : entries) {
    if (e.role != Role::Material) continue;
    const double r = table.of(e.material).cell_size;
    expected += e.source->volume() / (0.66 * r * r * r);
  }
  if (expected > static_cast<double>(job.max_vertices))
    throw InputError("the sizes asked for would give about " + std::to_string(static_cast<int64_t>(expected)) +
                     " vertices, more than limits.max_vertices = " + std::to_string(job.max_vertices) +
                     ": raise cell_size (check the model units: FreeCAD works in mm) or raise limits.max_vertices");
}

}  // namespace oraclemesh
