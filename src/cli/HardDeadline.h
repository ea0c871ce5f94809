#pragma once
// The CLI's last line of defence for limits.time_limit. The core checks the limit between its
// steps, but one call into OpenCASCADE on a damaged shape (sampling an edge, classifying a
// point) can loop for ever without reaching a checkpoint. A CLI process can always stop, so
// a watchdog ends it a grace period after the limit. Stuck inside OpenCASCADE on an input
// (job/OpenCascadeStall), it is that input's geometry, as when reading it hangs: exit
// code 2 and a message naming the input, its file and the fix. Stuck anywhere else, it is
// the job: exit code 3 naming the job and its phase. Either way output.report says so, as the
// core's own report of an unfinished job does (status, error, stopped_in). (oraclemesh.run
// cannot do that to its interpreter; run_isolated's worker does the same, and the batch
// workers kill their child.)
#include <algorithm>
#include <chrono>
#include <functional>
#include <condition_variable>
#include <cstdlib>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <fstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>


namespace oraclemesh::cli {

class HardDeadline {
 public:
  // Grace: a tenth of the limit, at least 2 s and at most 30 s, for the core's own checkpoint
  // to stop it first and write its partial mesh.
  // stalledInput(limit, grace, phase): the message when the job is stuck in OpenCASCADE on one of its
  // inputs (job/OpenCascadeStall.h), else empty.
  // reportPath: the job's output.report, or empty.
  HardDeadline(std::string jobPath, std::string reportPath, double timeLimitSeconds,
               std::function<std::string(double limit, double grace, const std::string& phase)> stalledInput)
      : jobPath_(std::move(jobPath)),
        reportPath_(std::move(reportPath)),
        limit_(timeLimitSeconds),
        grace_(std::min(30.0, std::max(2.0, 0.1 * limit_))),
        stalledInput_(std::move(stalledInput)) {
    watchdog_ = std::thread([this] { watch(); });
  }
  ~HardDeadline() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      finished_ = true;
    }
    wake_.notify_all();
    watchdog_.join();
  }
  HardDeadline(const HardDeadline&) = delete;
  HardDeadline& operator=(const HardDeadline&) = delete;

  // Called by the meshing thread as its progress enters a phase; the watchdog books the
  // seconds per phase itself, for the stuck thread's own clock cannot be read.
  void enterPhase(const std::string& phase) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    seconds_[phase_] += std::chrono::duration<double>(now - phaseStart_).count();
    phaseStart_ = now;
    phase_ = phase;
  }

 private:
  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_ + grace_);
    if (wake_.wait_until(lock, deadline, [this] { return finished_; })) return;
    const std::string stalled = stalledInput_(limit_, grace_, phase_);
    if (!stalled.empty()) {
      std::cerr << "\noraclemesh: error: " << stalled << "\n" << std::flush;
      writeReport("input_error", stalled);
      std::_Exit(2);  // as a file OpenCASCADE cannot finish reading: the input's fault
    }
    std::ostringstream text;
    text << "the job '" << jobPath_ << "' did not end within limits.time_limit = " << limit_ << " s (and " << grace_
         << " s of grace) and was stuck in phase '" << phase_
         << "': an input may be damaged (check it with Part > Check geometry or re-export it), or the sizes are too "
            "fine for the time limit (coarsen them or raise limits.time_limit)";
    const std::string message = text.str();
    std::cerr << "\noraclemesh: stopped: " << message << "\n" << std::flush;
    writeReport("stopped", message);
    std::_Exit(3);  // the stuck thread holds locks of its own: no destructors, no atexit handlers
  }

  // The stuck thread has written no report; this one has only what the watchdog knows: the
  // seconds per phase as the progress named them (stopped_in's names), and the total.
  void writeReport(const std::string& status, const std::string& message) const {
    if (reportPath_.empty()) return;
    const auto now = std::chrono::steady_clock::now();
    nlohmann::json seconds(seconds_);
    seconds[phase_] = seconds.value(phase_, 0.0) + std::chrono::duration<double>(now - phaseStart_).count();
    seconds["total"] = std::chrono::duration<double>(now - start_).count();
    const nlohmann::json report = {{"status", status}, {"error", message}, {"stopped_in", phase_}, {"seconds", seconds}};
    std::ofstream out(reportPath_);
    out << report.dump(2) << "\n" << std::flush;
  }

  std::string jobPath_, reportPath_;
  double limit_, grace_;
  std::function<std::string(double limit, double grace, const std::string& phase)> stalledInput_;
  std::string phase_ = "load";
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point phaseStart_ = start_;
  std::map<std::string, double> seconds_;  // of the phases left
  bool finished_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread watchdog_;
};

}  // namespace oraclemesh::cli
