#pragma once
// Dropping size samples the others already stand for. A sample (x, h) whose value the kept
// ones give at x to within a factor (1 + tolerance) adds at most that factor anywhere: the
// kept field is Lipschitz, so f(p) <= f(x) + g |p - x| <= (1 + tolerance) (h + g |p - x|).
// The face sampling puts a sample on every tessellation corner of every triangle around it
// and a curvature and a thickness sample at each point; most of them are such.
#include <vector>

#include "sizing/SizeField.h"

namespace oraclemesh {

// The samples, smallest first, less those whose size the already kept ones give within
// (1 + tolerance) at their point (checked against kept samples of the same size level and the
// two below, nearby in a grid of the level's size: a sample it misses is kept, never wrongly
// dropped). The order of the input decides ties only; the result does not depend on threads.
std::vector<SizeSample> thinSizeSamples(std::vector<SizeSample> samples, double grading, double tolerance);

}  // namespace oraclemesh
