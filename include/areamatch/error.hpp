#pragma once
/// \file error.hpp
/// The exceptions areamatch throws. Bad input (unreadable files, impossible parameters) throws;
/// "no good match" is never an exception but a result with `ok == false`.
///
///     std::runtime_error
///       └─ areamatch::error              every areamatch exception
///            ├─ areamatch::io_error      a file cannot be opened, read or written
///            │    └─ format_error        a file is readable but its content is invalid
///            └─ areamatch::parameter_error  a parameter or argument is out of its domain

#include <cmath>
#include <stdexcept>
#include <string>

namespace areamatch {

/// Base of every exception thrown by areamatch.
class error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file could not be opened, read or written. The message names the file.
class io_error : public error {
 public:
  using error::error;
};

/// A file was read but its content is not a valid image, map or manifest.
/// The message names the file and what is wrong with it.
class format_error : public io_error {
 public:
  using io_error::io_error;
};

/// A parameter is outside its domain (e.g. a resolution that is not a positive finite number).
/// The message names the parameter, its value and the allowed range.
class parameter_error : public error {
 public:
  using error::error;
};

/// An input is larger or more complex than a documented resource limit (e.g. more cells than
/// `max_grid_cells`, more Voronoi sites than `BoundaryParams::max_segments`, more areas than
/// `MatcherParams::max_areas`). The message names the limit and how to raise it.
class limit_error : public error {
 public:
  using error::error;
};

namespace detail {

/// Throws `parameter_error` "NAME must be positive and finite, got VALUE" unless value > 0.
inline void require_positive(double value, const std::string& name) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw parameter_error(name + " must be positive and finite, got " + std::to_string(value));
  }
}

/// Throws `parameter_error` "NAME must be >= 0 and finite, got VALUE" unless value ≥ 0.
inline void require_non_negative(double value, const std::string& name) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw parameter_error(name + " must be >= 0 and finite, got " + std::to_string(value));
  }
}

}  // namespace detail
}  // namespace areamatch
