#pragma once
// Which B-rep input the meshing thread is inside an OpenCASCADE call on, for a watchdog in
// another thread. A call looping on a damaged shape never returns to a checkpoint of the
// core; when the hard deadline (the CLI's, run_isolated's worker's) ends the process, this
// tells it the input's geometry is what was stuck (a bad input, exit code 2) rather than
// the core (a limit, exit code 3).
#include <atomic>
#include <string>

namespace oraclemesh {

class OpenCascadeWork {
 public:
  // Marks the calling thread as in OpenCASCADE on the input named `input` until destroyed
  // (scopes nest). `input` must outlive the scope: the solid's own name.
  explicit OpenCascadeWork(const std::string& input);
  ~OpenCascadeWork();
  OpenCascadeWork(const OpenCascadeWork&) = delete;
  OpenCascadeWork& operator=(const OpenCascadeWork&) = delete;

  // The calling thread becomes the one current() reports on (the job's meshing thread).
  // Threads not so marked (Python threads running jobs in-process) publish nothing.
  static void watchThisThread();
  // The name of the input the watched thread is in OpenCASCADE on; empty when none.
  static std::string current();

 private:
  const std::string* previous_;
};

}  // namespace oraclemesh
