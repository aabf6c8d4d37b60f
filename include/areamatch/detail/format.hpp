#pragma once
/// \file detail/format.hpp
/// Locale-independent number formatting for the text files and JSON areamatch writes.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace areamatch::detail {

/// The shortest "%g" text that reads back as exactly `value` (so files round-trip bit for bit).
/// Non-finite values are written as "nan"/"inf"/"-inf".
inline std::string format_double(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[40];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
    if (std::strtod(buffer, nullptr) == value) break;
  }
  return buffer;
}

/// `value` with a fixed number of decimals, for tables meant for people.
inline std::string format_fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

}  // namespace areamatch::detail
