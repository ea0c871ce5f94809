#pragma once
// The message of the InputError an action throws ("" when it throws none), for tests that
// check what a user is told.
#include <functional>
#include <string>

#include "Error.h"

namespace oraclemesh::test {

inline std::string inputErrorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace oraclemesh::test
