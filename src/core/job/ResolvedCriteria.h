#pragma once
// The job's criteria with every unset value filled from the model size, per material, and the
// up-front refusal of sizes that would exceed the vertex limit.
#include <vector>

#include "MeshCriteria.h"
#include "domain/HierarchicalOracle.h"
#include "job/JobSpec.h"
#include "sizing/Fineness.h"
#include "sizing/GeometrySizes.h"

namespace oraclemesh {

class RunControl;

// Defaults follow the bounding-box diagonal; per-material entries are merged over them.
// Throws InputError when criteria.materials names a material no input has, or when a size is
// below a millionth of the diagonal (naming the key it came from: wrong units).
CriteriaTable resolveCriteria(const JobSpec& job, double diagonal);

// The fineness preset the job asks for (criteria.fineness, unset = kDefaultFineness); nullptr
// for "off".
const FinenessPreset* jobFineness(const JobSpec& job);

// How many surface sizes a gap between two parts is wide, at every fineness: one keeps the
// faces on both sides apart with a margin (SizeFieldGaps' cubes stayed apart at twice it). A
// gap is not meshed, so more would only refine the faces that face it: the sizes per
// thickness of a preset are for walls, which are.
inline constexpr double kSizesPerGap = 1;

// Puts the sizing field of the job's fineness (sizing/GeometrySizes.h) into `table` (nothing
// when the job's fineness is off), and the sizes that keep gaps between B-rep inputs wider
// than `contactTolerance` open (at every fineness, "off" too), both capped by the largest cell
// size. Returns each pair's narrowest gap, narrowest first. Throws InputError when the sizes
// the geometry asks for would give more surface vertices than limits.max_vertices (naming the
// input, the smallest size, where and why; for a gap, the two parts, its width and the contact
// tolerance that would bond them).
std::vector<PartGap> attachSizeField(CriteriaTable& table, const JobSpec& job, const HierarchicalOracle& oracle,
                                     double contactTolerance, const RunControl& control);

// Throws InputError when the material entries' volumes at their cell sizes would give more
// vertices than limits.max_vertices.
void checkExpectedSize(const JobSpec& job, const HierarchicalOracle& oracle, const CriteriaTable& table);

}  // namespace oraclemesh
