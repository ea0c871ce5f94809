#pragma once
// Progress reporting, cancellation and the time limit, passed down through every phase.
// Long loops call checkpoint() often; it throws instead of returning a half-made result.
#include <atomic>
#include <chrono>
#include <algorithm>
#include <functional>
#include <limits>
#include <string>

#include "Error.h"

namespace oraclemesh {

class RunControl {
 public:
  using ProgressCallback = std::function<void(const std::string& phase, double fraction)>;

  RunControl() = default;
  RunControl(ProgressCallback progress, double timeLimitSeconds)
      : progress_(std::move(progress)), timeLimit_(timeLimitSeconds) {}

  void report(const std::string& phase, double fraction) const {
    if (progress_) progress_(phase, fraction);
  }
  void requestCancel() { cancelled_ = true; }
  bool cancelRequested() const { return cancelled_; }

  void checkpoint() const {
    if (cancelled_) throw Cancelled();
    if (timeLimit_ > 0 && elapsedSeconds() > timeLimit_)
      throw LimitError("meshing exceeded limits.time_limit = " + std::to_string(timeLimit_) +
                       " s: coarsen the sizes or raise limits.time_limit");
  }
  // Seconds left before the time limit; infinity when there is no limit.
  double remainingSeconds() const {
    return timeLimit_ > 0 ? std::max(0.0, timeLimit_ - elapsedSeconds()) : std::numeric_limits<double>::infinity();
  }
  double elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  ProgressCallback progress_;
  double timeLimit_ = 0;
  std::atomic<bool> cancelled_{false};
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace oraclemesh
