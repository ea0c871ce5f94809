#include "BatchCommand.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <vector>

#ifndef ORACLEMESH_PYTHON
#define ORACLEMESH_PYTHON "/usr/bin/python3"
#endif

namespace oraclemesh::cli {
namespace fs = std::filesystem;

namespace {

bool hasPackage(const fs::path& folder) {
  std::error_code ec;
  return fs::is_regular_file(folder / "oraclemesh" / "study" / "__main__.py", ec);
}

fs::path executableFolder(const char* argv0) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) return self.parent_path();
  return fs::absolute(argv0, ec).parent_path();
}

}  // namespace

BatchPython findBatchPython(const char* argv0) {
  BatchPython found;
  const char* python = std::getenv("ORACLEMESH_PYTHON");
  // The module is built for this interpreter (CMake's Python_EXECUTABLE).
  found.python = python && *python ? python : ORACLEMESH_PYTHON;
  const char* given = std::getenv("ORACLEMESH_PYTHONPATH");
  if (given && *given) {
    found.packageParent = given;
    return found;
  }
  // The build tree stages the package in <build>/python/oraclemesh next to <build>/oraclemesh.
  const fs::path folder = executableFolder(argv0);
  for (const fs::path& candidate : {folder / "python", folder.parent_path() / "python"})
    if (hasPackage(candidate)) {
      found.packageParent = candidate.string();
      break;
    }
  return found;
}

int runBatch(const char* argv0, int argc, char** args) {
  const BatchPython where = findBatchPython(argv0);
  if (!where.packageParent.empty()) {
    const char* old = std::getenv("PYTHONPATH");
    const std::string path = where.packageParent + (old && *old ? std::string(":") + old : std::string());
    setenv("PYTHONPATH", path.c_str(), 1);
  }
  std::vector<char*> command{const_cast<char*>(where.python.c_str()), const_cast<char*>("-m"),
                             const_cast<char*>("oraclemesh.study")};
  for (int i = 0; i < argc; ++i) command.push_back(args[i]);
  command.push_back(nullptr);
  execv(where.python.c_str(), command.data());
  std::cerr << "oraclemesh batch: cannot start " << where.python << ": " << std::strerror(errno)
            << " (set ORACLEMESH_PYTHON to the Python 3 the module was built for)\n";
  return 2;
}

}  // namespace oraclemesh::cli
