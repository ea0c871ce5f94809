#pragma once
// `oraclemesh batch ...`: the batch runner is the Python package (oraclemesh.study, on Dask),
// so this command replaces the process by `python3 -m oraclemesh.study ...`.
#include <string>

namespace oraclemesh::cli {

// The interpreter, the folder put first on PYTHONPATH, and where they came from, for --help.
struct BatchPython {
  std::string python;
  std::string packageParent;  // empty: none found, the interpreter's own sys.path is used
};
BatchPython findBatchPython(const char* argv0);

// Execs the batch runner with args (after "batch"); returns only when exec failed (exit code).
int runBatch(const char* argv0, int argc, char** args);

}  // namespace oraclemesh::cli
