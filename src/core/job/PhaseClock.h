#pragma once
// Wall-clock seconds per phase of a job (report.seconds): each finish() books the time since
// the previous one under its phase's name.
#include <chrono>
#include <map>
#include <string>

namespace oraclemesh {

class PhaseClock {
 public:
  void finish(const std::string& phase) {
    const auto now = std::chrono::steady_clock::now();
    seconds[phase] += std::chrono::duration<double>(now - start_).count();
    start_ = now;
  }
  std::map<std::string, double> seconds;

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace oraclemesh
