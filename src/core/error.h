// Typed errors for configuration and I/O boundaries. The library throws these with a
// message naming the input and the problem; it never calls exit().
#pragma once

#include <stdexcept>
#include <string>

namespace plslam {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file that is missing, unreadable, truncated or malformed.
class IoError : public Error {
 public:
  using Error::Error;
};

/// Options or command-line arguments that are unknown, of the wrong type or out of range.
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// Input data that is readable but inconsistent (wrong image size, bad intrinsics...).
class DataError : public Error {
 public:
  using Error::Error;
};

}  // namespace plslam
