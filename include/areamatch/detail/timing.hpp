#pragma once
/// \file detail/timing.hpp
/// Wall-clock seconds, for the timings that results report.

#include <chrono>

namespace areamatch::detail {

using Clock = std::chrono::steady_clock;

inline double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

inline double seconds_since(Clock::time_point start) { return seconds_between(start, Clock::now()); }

}  // namespace areamatch::detail
