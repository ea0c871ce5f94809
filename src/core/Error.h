#pragma once
// Errors that reach users. Every message names the input it is about and the fix,
// because the person reading it is a FEM engineer in FreeCAD, not a C++ developer.
#include <stdexcept>
#include <string>

namespace oraclemesh {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// The job or one of its inputs is unusable (bad file, open shell, bad size...).
class InputError : public Error {
 public:
  using Error::Error;
};

// An engine made no tetrahedron at all: the sizes are larger than every part, or an input
// encloses (almost) nothing. The pipeline adds which inputs and what they enclose.
class NoTetrahedraError : public InputError {
 public:
  using InputError::InputError;
};

// The mesher stopped on a limit (vertex count, time) or was cancelled.
class LimitError : public Error {
 public:
  using Error::Error;
};

class Cancelled : public Error {
 public:
  Cancelled() : Error("meshing was cancelled") {}
};

}  // namespace oraclemesh
