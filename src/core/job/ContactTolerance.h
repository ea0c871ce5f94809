#pragma once
// The job's contact tolerance (issue 16 item 3): parts closer than it touch and are bonded,
// parts farther apart stay apart. One value per job, used by the gap sizing
// (sizing/GeometrySizes) and the self-check's joined-parts test (job/JoinedParts).
#include <string>

#include "domain/HierarchicalOracle.h"
#include "job/JobSpec.h"

namespace oraclemesh {

struct LoadedInputs;  // job/InputLoading.h

struct ContactTolerance {
  double value = 0;
  // Where the value comes from: "job" (contact_tolerance), "diagonal" (1e-6 of it), "shape
  // tolerance of input 'X'" or "STEP uncertainty of input 'X'".
  std::string from;
};

// The job's contact_tolerance when given; else the largest of 1e-6 of the diagonal, the
// largest OpenCASCADE tolerance of any B-rep input's faces, edges and vertices, the job's
// cad_uncertainty and the largest uncertainty a STEP input declares (the CAD tool's own idea
// of touching).
ContactTolerance contactTolerance(const JobSpec& job, const HierarchicalOracle& oracle, const LoadedInputs& inputs);

}  // namespace oraclemesh
