#pragma once
/// \file Typed exceptions for broken contracts (see STYLE.md, "Errors, three kinds").
#include <stdexcept>
#include <string>

namespace kerfab {

/// Base of every kerfab exception; what() is one line that names the file, element or value.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The input (mesh, option, guidance file) violates a documented precondition. CLI exit code 1.
class InvalidInput : public Error {
 public:
  using Error::Error;
};

/// A file could not be read or written. CLI exit code 2.
class IoError : public Error {
 public:
  using Error::Error;
};

/// A solver failed to produce any usable answer. CLI exit code 3.
class SolverError : public Error {
 public:
  using Error::Error;
};

}  // namespace kerfab
