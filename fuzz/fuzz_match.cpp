// Fuzz target: the matcher on pairs of arbitrary small grids. Any result is fine; a crash,
// sanitizer report, non-finite transform on an ok result, or an exception that is not an
// areamatch::error is a finding.
#include <areamatch/areamatch.hpp>

#include "fuzz_support.hpp"

#include <cmath>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::size_t half = size / 2;
  const std::uint8_t* first = data;
  std::size_t first_size = half;
  const std::uint8_t* second = data + half;
  std::size_t second_size = size - half;
  const areamatch::OccupancyGrid source = areamatch_fuzz::grid_from_bytes(first, first_size);
  const areamatch::OccupancyGrid dest = areamatch_fuzz::grid_from_bytes(second, second_size);
  if (source.empty() || dest.empty()) return 0;
  try {
    areamatch::Matcher<> matcher;
    matcher.params.allow_reflection = (size % 2) == 1;
    const areamatch::MatchResult r = matcher.match(source, dest);
    if (r.ok && !(std::isfinite(r.T_dest_source.rotation) && r.T_dest_source.translation.allFinite() &&
                  std::isfinite(r.score))) {
      std::abort();
    }
  } catch (const areamatch::error&) {
  }
  return 0;
}
