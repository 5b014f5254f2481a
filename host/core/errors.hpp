// Typed errors. The library throws these; only main() turns them into exit codes
// (InputError -> 2, everything else -> 1; see README "When things go wrong").
#pragma once
#include <stdexcept>
#include <string>

namespace pdmesh {

// Base of every pdmesh error.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bad user input: a file, a case-file key, a command-line value. Exit status 2.
// The message names the file, the line (or object) and the value.
class InputError : public Error {
 public:
  using Error::Error;
};

// Geometry that cannot mesh: unclosed loops, intersecting curves, zero-length segments. Exit status 2.
class GeometryError : public InputError {
 public:
  using InputError::InputError;
};

// Valid input that would need unreasonable resources (too many nodes, unresolvable spacing). Exit status 2.
class LimitError : public InputError {
 public:
  using InputError::InputError;
};

// OpenCL platform, build or run-time failure. Exit status 1.
class DeviceError : public Error {
 public:
  using Error::Error;
};

// A simulation that went wrong (NaN, a node outside the domain that cannot be snapped). Exit status 1.
class SimulationError : public Error {
 public:
  using Error::Error;
};

}  // namespace pdmesh
