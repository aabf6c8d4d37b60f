#pragma once
// Shared by the fuzz targets: turning fuzzer bytes into small occupancy grids, and the rule that
// bad input may throw an areamatch::error but nothing else (any other exception, crash,
// sanitizer report or hang is a finding).
#include <areamatch/grid.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace areamatch_fuzz {

/// A grid of up to 64 × 64 cells from the bytes: the first byte gives the width (1..64), the
/// second the resolution (0.02..0.275 m), then each byte gives four cells, 2 bits each (0 free,
/// 1 occupied, 2 and 3 unknown). Consumes what it uses from data/size.
inline areamatch::OccupancyGrid grid_from_bytes(const std::uint8_t*& data, std::size_t& size) {
  if (size < 2) return {};
  const int width = 1 + data[0] % 64;
  const double resolution = 0.02 + 0.001 * data[1];
  data += 2;
  size -= 2;
  const std::size_t cells = std::min<std::size_t>(size * 4, 64 * 64);
  const int height = static_cast<int>(std::max<std::size_t>(1, cells / static_cast<std::size_t>(width)));
  areamatch::OccupancyGrid grid(width, height, resolution);
  for (int i = 0; i < width * height; ++i) {
    const std::size_t byte = static_cast<std::size_t>(i) / 4;
    const int bits = byte < size ? (data[byte] >> (2 * (i % 4))) & 3 : 1;
    grid.set(i % width, i / width, bits == 0 ? areamatch::CellState::free
                                   : bits == 1 ? areamatch::CellState::occupied : areamatch::CellState::unknown);
  }
  const std::size_t used = std::min(size, (static_cast<std::size_t>(width * height) + 3) / 4);
  data += used;
  size -= used;
  return grid;
}

}  // namespace areamatch_fuzz
