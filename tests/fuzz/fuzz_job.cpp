// The job parser: any text gives a JobSpec or an InputError (a message for the user). Any
// other exception, a crash or a sanitizer report is a finding.
#include <cstdint>
#include <string>

#include "Error.h"
#include "job/JobSpec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    oraclemesh::JobSpec::fromJsonText(text, "/nonexistent-job-folder");
  } catch (const oraclemesh::InputError&) {
  }
  return 0;
}
