#pragma once
// What a hard deadline (the CLI's, run_isolated's worker's) says when it ends a job whose
// meshing thread is inside OpenCASCADE on one of the job's B-rep inputs (domain/OpenCascadeWork):
// as a file OpenCASCADE cannot finish reading, that input's geometry is the cause, so it is a
// bad input (exit code 2, InputError) naming the input, its file and the fix.
#include <string>

#include "job/JobSpec.h"

namespace oraclemesh {

// The message; empty when the watched thread is not in OpenCASCADE (then the job is stuck
// in the core: a limit, exit code 3).
std::string openCascadeStallMessage(const JobSpec& job, double timeLimit, double grace, const std::string& phase);

}  // namespace oraclemesh
