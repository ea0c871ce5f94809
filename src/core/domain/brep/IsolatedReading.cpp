// Both sides of the helper process that reads B-rep files: the caller (spawn, wait within the
// time limit and cancel, outcome as an error naming the file) and the helper's main.
#include "domain/brep/IsolatedReading.h"

#include <BRep_Builder.hxx>
#include <BinTools.hxx>
#include <Standard_Failure.hxx>
#include <TopoDS_Compound.hxx>

#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "Error.h"
#include "RunControl.h"
#include "domain/BrepSolid.h"
#include "domain/brep/FiniteGeometry.h"

extern char** environ;

namespace oraclemesh {

namespace fs = std::filesystem;

namespace {

constexpr const char* kHelperName = "oraclemesh-shape-reader";
constexpr const char* kHelperVariable = "ORACLEMESH_SHAPE_READER";
constexpr int kExitInputError = 2;
constexpr int kExitOtherError = 3;

std::string readWholeFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeWholeFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw Error("cannot write " + path.string());
}

// Where the core's code lives: the CLI, the Python module or a test program.
fs::path folderOfThisCode() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&folderOfThisCode), &info) && info.dli_fname && std::strchr(info.dli_fname, '/')) {
    std::error_code ec;
    const fs::path file = fs::weakly_canonical(info.dli_fname, ec);
    if (!ec) return file.parent_path();
  }
  return {};
}

std::vector<fs::path> helperCandidates() {
  std::vector<fs::path> folders;
  if (const fs::path code = folderOfThisCode(); !code.empty()) folders.push_back(code);
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) folders.push_back(self.parent_path());
  std::vector<fs::path> candidates;
  for (const fs::path& folder : folders) {
    candidates.push_back(folder / kHelperName);
    candidates.push_back(folder.parent_path() / "libexec" / "oraclemesh" / kHelperName);
  }
  return candidates;
}

std::string findHelper() {
  if (const char* given = std::getenv(kHelperVariable); given && *given) return given;
  std::string looked;
  for (const fs::path& candidate : helperCandidates()) {
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    looked += (looked.empty() ? "" : ", ") + candidate.string();
  }
  throw Error(std::string("OracleMesh cannot find its helper program ") + kHelperName + " (looked for " + looked +
              "): reinstall OracleMesh, or set " + kHelperVariable + " to the program's path");
}

// A private temporary folder, removed with everything in it.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "oraclemesh-read-XXXXXX").string();
    if (!::mkdtemp(pattern.data()))
      throw Error("cannot create a temporary folder in " + fs::temp_directory_path().string() + ": " +
                  std::strerror(errno) + "; free disk space or set TMPDIR");
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

pid_t spawnHelper(const std::string& helper, const std::vector<std::string>& args, const fs::path& log) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(helper.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  // The caller (Python, FreeCAD) may block or ignore signals; the helper starts with defaults.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &all);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = 0;
  const int failed = posix_spawn(&pid, helper.c_str(), &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (failed)
    throw Error("OracleMesh cannot start its helper program " + helper + ": " + std::strerror(failed) +
                "; reinstall OracleMesh, or set " + kHelperVariable + " to the program's path");
  return pid;
}

void killAndReap(pid_t pid) {
  ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
}

std::string seconds(double s) {
  std::ostringstream text;
  text << s;
  return text.str();
}

struct HelperOutput {
  TopoDS_Shape solids;
  std::vector<std::string> warnings;
  double declared_uncertainty = 0;
};

// The helper's solids travel as binary BREP: the text format rounds vertices and edge
// ranges to 15 digits, which would make the mesh differ from one made in-process.
TopoDS_Shape readBinaryBrep(const fs::path& file, const std::string& what) {
  TopoDS_Shape shape;
  try {
    if (!BinTools::Read(shape, file.c_str())) shape.Nullify();
  } catch (const Standard_Failure&) {
    shape.Nullify();
  }
  if (shape.IsNull())
    throw Error("the solids of " + what + " did not come back from the helper program; please report this");
  return shape;
}

// Runs the helper on one input and waits for it within the time limit and cancel; every way
// it can end other than success is an error naming `what`.
HelperOutput readInHelper(const std::string& kind, const std::string& input, const TemporaryFolder& folder,
                          const std::string& name, BrepSolid::Grouping grouping, const std::string& what,
                          const RunControl& control, double progress) {
  const std::string helper = findHelper();
  const fs::path log = folder.path() / "log.txt";
  const pid_t pid = spawnHelper(helper,
                                {kind, input, folder.path().string(), name,
                                 grouping == BrepSolid::Grouping::Together ? "together" : "separate",
                                 std::to_string(::getpid())},
                                log);
  const auto started = std::chrono::steady_clock::now();
  auto nextReport = started;
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) throw Error(std::string("waiting for the helper failed: ") + std::strerror(errno));
    if (control.cancelRequested()) {
      killAndReap(pid);
      throw Cancelled();
    }
    if (control.remainingSeconds() <= 0) {
      killAndReap(pid);
      throw InputError("OpenCASCADE did not finish reading " + what + " within limits.time_limit (" +
                       seconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()) +
                       " s of reading); check it with Part > Check geometry or re-export it, or raise "
                       "limits.time_limit if it is merely large");
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= nextReport) {  // a Python progress callback can cancel only when it is called
      control.report("load", progress);
      nextReport = now + std::chrono::milliseconds(250);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    HelperOutput output;
    output.solids = readBinaryBrep(folder.path() / "solids.bin", what);
    std::istringstream lines(readWholeFile(folder.path() / "warnings.txt"));
    for (std::string line; std::getline(lines, line);)
      if (!line.empty()) output.warnings.push_back(line);
    output.declared_uncertainty = std::strtod(readWholeFile(folder.path() / "uncertainty.txt").c_str(), nullptr);
    return output;
  }
  const std::string message = readWholeFile(folder.path() / "error.txt");
  if (WIFEXITED(status) && WEXITSTATUS(status) == kExitInputError && !message.empty()) throw InputError(message);
  if (WIFEXITED(status) && WEXITSTATUS(status) == kExitOtherError && !message.empty())
    throw InputError("OpenCASCADE failed on " + what + ": " + message +
                     (message.find("Part > Check geometry") == std::string::npos
                          ? "; check it with Part > Check geometry or re-export it"
                          : ""));
  std::string how = WIFSIGNALED(status) ? std::string("signal ") + std::to_string(WTERMSIG(status)) + ", " +
                                              strsignal(WTERMSIG(status))
                                        : "exit code " + std::to_string(WEXITSTATUS(status));
  throw InputError("OpenCASCADE crashed reading " + what + " (" + how +
                   "); check it with Part > Check geometry or re-export it");
}

// The queries the mesher makes first, once each on a coarse grid: on a shape where OpenCASCADE's
// classifier or intersector loops (a damaged BREP), they loop here, in the helper, not in the mesher.
void probeQueries(const BrepSolid& solid) {
  const Bbox box = solid.bbox();
  auto at = [&](double u, double v, double w) {
    return Point3{box.min[0] + u * (box.max[0] - box.min[0]), box.min[1] + v * (box.max[1] - box.min[1]),
                  box.min[2] + w * (box.max[2] - box.min[2])};
  };
  constexpr int n = 4;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Point3 p = at((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
        solid.insideByOpenCascade(p);
        solid.insideExact(p);
        solid.inside(p);
      }
  for (int axis = 0; axis < 3; ++axis) {
    Point3 a = at(0.5, 0.5, 0.5), b = a;
    a[axis] = box.min[axis] - 0.1 * (box.max[axis] - box.min[axis]);
    b[axis] = box.max[axis] + 0.1 * (box.max[axis] - box.min[axis]);
    solid.crossings(a, b);
  }
  solid.crossings(at(-0.1, -0.1, -0.1), at(1.1, 1.1, 1.1));
}

std::string describe(const std::string& name, const std::string& path) {
  return "input '" + name + "'" + (path.empty() ? " (BREP text)" : " (file '" + path + "')");
}

BrepSolid::Loaded loadHelperOutput(HelperOutput output, const std::string& name, BrepSolid::Grouping grouping,
                                   const std::string& path) {
  const std::string what = describe(name, path);
  // The helper tessellated the solids; their triangles came back with them.
  BrepSolid::Loaded loaded = BrepSolid::load(output.solids, name, grouping, path, BrepSolid::Tessellation::Reuse);
  output.warnings.insert(output.warnings.end(), loaded.warnings.begin(), loaded.warnings.end());
  loaded.warnings = std::move(output.warnings);
  loaded.declared_uncertainty = output.declared_uncertainty;
  return loaded;
}

}  // namespace

BrepSolid::Loaded BrepSolid::loadFileIsolated(const std::string& path, const std::string& name, Grouping grouping,
                                              const RunControl& control, double progress) {
  TemporaryFolder folder;
  return loadHelperOutput(
      readInHelper("--file", path, folder, name, grouping, describe(name, path), control, progress), name,
      grouping, path);
}

BrepSolid::Loaded BrepSolid::loadBrepTextIsolated(const std::string& text, const std::string& name,
                                                  Grouping grouping, const RunControl& control, double progress) {
  TemporaryFolder folder;
  const fs::path input = folder.path() / "input.brep";
  writeWholeFile(input, text);
  return loadHelperOutput(
      readInHelper("--text", input.string(), folder, name, grouping, describe(name, ""), control, progress), name,
      grouping, "");
}

int shapeReaderMain(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr,
                 "usage: %s --file PATH | --text FILE  OUTDIR NAME separate|together PARENT_PID\n"
                 "  OracleMesh's helper: reads and checks one B-rep input apart from the mesher.\n",
                 argv[0]);
    return 64;
  }
  // Ends with the caller, so a killed mesher leaves no reader behind.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (std::to_string(::getppid()) != argv[6]) return kExitOtherError;
  const std::string kind = argv[1], input = argv[2], name = argv[4];
  const fs::path out = argv[3];
  const auto grouping = std::string(argv[5]) == "together" ? BrepSolid::Grouping::Together : BrepSolid::Grouping::Separate;
  const std::string what = describe(name, kind == "--text" ? "" : input);
  try {
    try {
      const BrepSolid::Loaded loaded = kind == "--text" ? BrepSolid::loadBrepText(readWholeFile(input), name, grouping)
                                                        : BrepSolid::loadFile(input, name, grouping);
      BRep_Builder builder;
      TopoDS_Compound solids;
      builder.MakeCompound(solids);
      for (const auto& solid : loaded.solids) {
        probeQueries(*solid);
        builder.Add(solids, solid->shape());
      }
      const fs::path file = out / "solids.bin";
      if (!BinTools::Write(solids, file.c_str())) throw Error("cannot write " + file.string());
      // What the caller will read must read back here first.
      requireFiniteGeometry(readBinaryBrep(file, what), what);
      std::string warnings;
      for (const std::string& w : loaded.warnings) warnings += w + "\n";
      writeWholeFile(out / "warnings.txt", warnings);
      char uncertainty[32];  // 17 digits: the double itself comes back
      std::snprintf(uncertainty, sizeof uncertainty, "%.17g", loaded.declared_uncertainty);
      writeWholeFile(out / "uncertainty.txt", uncertainty);
      return 0;
    } catch (const InputError& e) {
      writeWholeFile(out / "error.txt", e.what());
      return kExitInputError;
    } catch (const std::exception& e) {
      writeWholeFile(out / "error.txt", e.what());
      return kExitOtherError;
    }
  } catch (...) {
    return kExitOtherError;
  }
}

}  // namespace oraclemesh
