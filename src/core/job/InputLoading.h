#pragma once
// The job's inputs as oracle entries, highest priority first: files (B-rep, triangle surfaces),
// B-rep text, spheres, surfaces given inline and labelled images (one entry per mapped label).
#include <string>
#include <vector>

#include "RunControl.h"
#include "domain/HierarchicalOracle.h"
#include "job/JobReport.h"
#include "job/JobSpec.h"

namespace oraclemesh {

// Every entry of every input, with per entry what kind of input it is ("B-rep solid",
// "triangle surface", ...) and the name of the job input it came from (a B-rep file with
// several solids gives one entry per solid), and the warnings of loading them.
struct LoadedInputs {
  std::vector<OracleEntry> entries;
  std::vector<std::string> kinds;
  std::vector<std::string> inputs;
  std::vector<std::string> warnings;
  // The largest length uncertainty a STEP input declares (model units, 0: none) and that
  // input's name (job/ContactTolerance).
  double declared_uncertainty = 0;
  std::string declared_uncertainty_by;
};

// Reports progress as phase "load" and checks for cancellation after each input. Throws
// InputError naming the input when one cannot be read.
LoadedInputs loadInputs(const JobSpec& job, const RunControl& control);

// report.inputs: the oracle's entries (made from `loaded`) with their kinds and inputs.
std::vector<InputReport> describeInputs(const HierarchicalOracle& oracle, const LoadedInputs& loaded);

}  // namespace oraclemesh
