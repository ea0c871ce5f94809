// `oraclemesh JOB.json`: runs a job file, progress on stderr, a one-screen summary on stdout.
// `oraclemesh batch ...`: many jobs on a Dask cluster (BatchCommand.h).
// Exit codes: 0 done, 2 bad job or input (also OpenCASCADE stuck on an input's geometry past
// the time limit), 3 limit reached (time, vertices, memory) or cancelled, 1 anything else.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <new>
#include <sstream>
#include <thread>

#include "BatchCommand.h"
#include "HardDeadline.h"
#include "Error.h"
#include "domain/OpenCascadeWork.h"
#include "job/JobJson.h"
#include "job/OpenCascadeStall.h"
#include "job/Pipeline.h"

namespace {

int usage(const char* argv0) {
  const oraclemesh::cli::BatchPython python = oraclemesh::cli::findBatchPython(argv0);
  std::cerr << "usage: oraclemesh JOB.json\n"
               "  Meshes the inputs of the job file (see README.md, 'The job contract') and writes\n"
               "  the files listed in output.files and output.report. Relative paths in the job are\n"
               "  relative to the job file's folder.\n"
               "  \"engine\": \"thesis\" (default; Rule Set T, constrained sharp edges) or \"cgal\"\n"
               "  (CGAL Mesh_3 with protecting balls).\n"
               "usage: oraclemesh batch JOBS... --out DIR [--workers N | --scheduler ADDRESS] [...]\n"
               "  Meshes many jobs (job files, folders of them, study files) on a Dask cluster, a\n"
               "  local one by default, into DIR/results.csv and DIR/results.json; `oraclemesh batch\n"
               "  --help` lists the options. Runs `"
            << python.python << " -m oraclemesh.study` with "
            << (python.packageParent.empty() ? std::string("its own sys.path (no build python/ folder found)")
                                             : python.packageParent + " first on PYTHONPATH")
            << "\n  (found next to this executable; ORACLEMESH_PYTHONPATH and ORACLEMESH_PYTHON override).\n";
  return 2;
}

void printSummary(const nlohmann::json& report) {
  const auto& counts = report["counts"];
  std::cout << "vertices " << counts["vertices"] << ", tets " << counts["tets"] << "\n";
  for (const auto& [material, n] : counts["tets_per_material"].items())
    std::cout << "  material " << material << ": " << n << " tets\n";
  std::cout << "dihedral angles: min " << report["quality"]["min_dihedral_deg"] << ", max "
            << report["quality"]["max_dihedral_deg"] << " degrees\n";
  for (const auto& [phase, s] : report["seconds"].items()) std::cout << "  " << phase << ": " << s << " s\n";
  for (const auto& w : report["warnings"]) std::cout << "warning: " << w.get<std::string>() << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "batch") return oraclemesh::cli::runBatch(argv[0], argc - 2, argv + 2);
  if (argc != 2 || std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help") return usage(argv[0]);
  const std::string jobPath = argv[1];
  try {
    oraclemesh::jobjson::requireJobFileSize(jobPath);  // before reading a byte of it
    std::ifstream in(jobPath);
    if (!in) throw oraclemesh::InputError("cannot read the job file '" + jobPath + "': check the path");
    std::stringstream text;
    text << in.rdbuf();
    const std::string base = std::filesystem::absolute(jobPath).parent_path().string();
    const oraclemesh::JobSpec job = oraclemesh::JobSpec::fromJsonText(text.str(), base);
    oraclemesh::OpenCascadeWork::watchThisThread();
    oraclemesh::cli::HardDeadline deadline(jobPath, job.report_file, job.time_limit,
                                           [&job](double limit, double grace, const std::string& phase) {
                                             return oraclemesh::openCascadeStallMessage(job, limit, grace, phase);
                                           });
    // Test hook: ORACLEMESH_CLI_STALL=<phase> blocks the meshing thread when that phase starts,
    // as a call stuck inside the core would, so that tests can see the deadline end it;
    // ORACLEMESH_CLI_STALL=opencascade:<phase> blocks it as inside OpenCASCADE on the first input.
    const char* stallVariable = std::getenv("ORACLEMESH_CLI_STALL");
    std::string stall = stallVariable ? stallVariable : "";
    const bool stallInOpenCascade = stall.rfind("opencascade:", 0) == 0;
    if (stallInOpenCascade) stall = stall.substr(std::string("opencascade:").size());
    std::string lastPhase;
    oraclemesh::RunControl control(
        [&](const std::string& phase, double fraction) {
          if (phase != lastPhase) {
            std::cerr << "\n";
            deadline.enterPhase(phase);
            if (!stall.empty() && phase == stall) {
              std::unique_ptr<oraclemesh::OpenCascadeWork> working;
              if (stallInOpenCascade) working = std::make_unique<oraclemesh::OpenCascadeWork>(job.inputs.front().name);
              std::this_thread::sleep_for(std::chrono::hours(24));
            }
          }
          lastPhase = phase;
          std::cerr << "\r[oraclemesh] " << phase << " " << static_cast<int>(100 * fraction) << "%" << std::flush;
        },
        job.time_limit);
    const oraclemesh::JobResult result = oraclemesh::runJob(job, control);
    std::cerr << "\n";
    printSummary(result.report);
    return 0;
  } catch (const oraclemesh::InputError& e) {
    std::cerr << "\noraclemesh: error: " << e.what() << "\n";
    return 2;
  } catch (const oraclemesh::LimitError& e) {
    std::cerr << "\noraclemesh: stopped: " << e.what() << "\n";
    return 3;
  } catch (const oraclemesh::Cancelled& e) {
    std::cerr << "\noraclemesh: " << e.what() << "\n";
    return 3;
  } catch (const std::bad_alloc&) {
    std::cerr << "\noraclemesh: stopped: " << oraclemesh::kOutOfMemoryMessage << "\n";
    return 3;
  } catch (const oraclemesh::Error& e) {  // not the input's fault (a file system error, ...) but explained
    std::cerr << "\noraclemesh: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "\noraclemesh: internal error: " << e.what() << "\n";
    return 1;
  }
}
