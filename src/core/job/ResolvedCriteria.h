#pragma once
// The job's criteria with every unset value filled from the model size, per material, and the
// up-front refusal of sizes that would exceed the vertex limit.
#include <vector>

#include "MeshCriteria.h"
#include "domain/HierarchicalOracle.h"
#include "job/JobSpec.h"

namespace oraclemesh {

// Defaults follow the bounding-box diagonal; per-material entries are merged over them.
// Throws InputError when criteria.materials names a material no input has, or when a size is
// below a millionth of the diagonal (naming the key it came from: wrong units).
CriteriaTable resolveCriteria(const JobSpec& job, double diagonal);

// Throws InputError when the material entries' volumes at their cell sizes would give more
// vertices than limits.max_vertices.
void checkExpectedSize(const JobSpec& job, const std::vector<OracleEntry>& entries, const CriteriaTable& table);

}  // namespace oraclemesh
