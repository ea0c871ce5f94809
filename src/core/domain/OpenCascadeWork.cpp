#include "domain/OpenCascadeWork.h"

namespace oraclemesh {

namespace {

// Per thread, so that scopes of threads nobody watches cannot leave a dangling name behind.
thread_local std::atomic<const std::string*> inputOfThisThread{nullptr};
std::atomic<std::atomic<const std::string*>*> watchedThread{nullptr};

}  // namespace

OpenCascadeWork::OpenCascadeWork(const std::string& input)
    : previous_(inputOfThisThread.exchange(&input, std::memory_order_release)) {}

OpenCascadeWork::~OpenCascadeWork() { inputOfThisThread.store(previous_, std::memory_order_release); }

void OpenCascadeWork::watchThisThread() { watchedThread.store(&inputOfThisThread, std::memory_order_release); }

std::string OpenCascadeWork::current() {
  const std::atomic<const std::string*>* slot = watchedThread.load(std::memory_order_acquire);
  const std::string* input = slot ? slot->load(std::memory_order_acquire) : nullptr;
  return input ? *input : std::string();
}

}  // namespace oraclemesh
