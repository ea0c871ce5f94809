#include "job/ContactTolerance.h"

#include <ShapeAnalysis_ShapeTolerance.hxx>

#include "domain/BrepTopology.h"
#include "job/InputLoading.h"

namespace oraclemesh {

ContactTolerance contactTolerance(const JobSpec& job, const HierarchicalOracle& oracle, const LoadedInputs& inputs) {
  if (job.contact_tolerance) return {*job.contact_tolerance, "job"};
  ContactTolerance tolerance{1e-6 * oracle.diagonal(), "diagonal"};
  for (const OracleEntry& entry : oracle.entries()) {
    const BrepTopology* solid = entry.source->brepTopology();
    if (!solid) continue;
    // Mode 1: the largest over the shape's faces, edges and vertices.
    const double own = ShapeAnalysis_ShapeTolerance().Tolerance(solid->shape(), 1);
    if (own > tolerance.value) tolerance = {own, "shape tolerance of input '" + solid->name() + "'"};
  }
  if (job.cad_uncertainty > tolerance.value) tolerance = {job.cad_uncertainty, "cad_uncertainty (job)"};
  if (inputs.declared_uncertainty > tolerance.value)
    tolerance = {inputs.declared_uncertainty, "STEP uncertainty of input '" + inputs.declared_uncertainty_by + "'"};
  return tolerance;
}

}  // namespace oraclemesh
