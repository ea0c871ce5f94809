#include "job/OpenCascadeStall.h"

#include <sstream>

#include "domain/OpenCascadeWork.h"

namespace oraclemesh {

namespace {

// "input 'm#2' (file 'm.step')" for solid 2 of the job's input 'm' (the names BrepSolid loads).
std::string describeBrepInput(const JobSpec& job, const std::string& solid) {
  for (const InputSpec& input : job.inputs) {
    if (solid != input.name && solid.rfind(input.name + "#", 0) != 0) continue;
    if (input.kind == InputSpec::Kind::File) return "input '" + solid + "' (file '" + input.file + "')";
    if (input.kind == InputSpec::Kind::BrepText) return "input '" + solid + "' (BREP text)";
  }
  return "input '" + solid + "'";
}

}  // namespace

std::string openCascadeStallMessage(const JobSpec& job, double timeLimit, double grace, const std::string& phase) {
  const std::string solid = OpenCascadeWork::current();
  if (solid.empty()) return "";
  std::ostringstream message;
  message << "OpenCASCADE did not finish working on " << describeBrepInput(job, solid)
          << " within limits.time_limit = " << timeLimit << " s (and " << grace << " s of grace), in phase '" << phase
          << "': the shape is damaged there or too complex for the time limit; check it with Part > Check geometry "
             "and repair it or export it again from the CAD tool (a sound shape that is only large needs a larger "
             "limits.time_limit)";
  return message.str();
}

}  // namespace oraclemesh
