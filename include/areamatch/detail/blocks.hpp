#pragma once
/// \file detail/blocks.hpp
/// Loops over cells that GCC vectorises at -O2 as well as -O3. At -O2 it vectorises only loops
/// that need no runtime alias check and no scalar remainder; a per-cell kernel written as a
/// small function with `__restrict` parameters and called on fixed blocks by `in_blocks` needs
/// neither. (Run scalar, the erosion of office_g took 20 ms instead of 2.)

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace areamatch::detail {

/// Cells per block: two 16-byte vectors of byte cells.
constexpr int block_cells = 32;

/// Calls kernel(first, count) on [begin, end) cut into blocks of `block_cells` (the last one
/// shorter); the compiler sees the constant count when it inlines the kernel.
template <class Kernel>
inline void in_blocks(int begin, int end, Kernel&& kernel) {
  int c = begin;
  for (; c + block_cells <= end; c += block_cells) kernel(c, block_cells);
  if (c < end) kernel(c, end - c);
}

/// Byte scans over rows of a mask, 8 bytes per step where the platform allows: maps are long
/// runs of equal cells, and a byte-by-byte search was most of finding runs on large maps.
#if defined(__GNUC__) && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define AREAMATCH_WORD_SCAN 1
#endif

/// The zero bytes of `x` with their high bit set, and nothing else (no carries across bytes).
inline std::uint64_t zero_byte_marks(std::uint64_t x) {
  constexpr std::uint64_t low7 = 0x7F7F7F7F7F7F7F7FULL;
  return ~(((x & low7) + low7) | x | low7);
}

/// The first index in [from, to) where `wanted(byte)` holds, or `to`. Word by word,
/// `marks(word ^ pattern)` (pattern = `value` in every byte) must be non-zero exactly when the
/// word holds a wanted byte, its lowest set bit in the first one.
template <class Marks, class Wanted>
int find_first_byte(const std::uint8_t* row, int from, int to, std::uint8_t value, Marks&& marks, Wanted&& wanted) {
  int c = from;
#ifdef AREAMATCH_WORD_SCAN
  const std::uint64_t pattern = 0x0101010101010101ULL * value;
  for (; c + 8 <= to; c += 8) {
    std::uint64_t word;
    std::memcpy(&word, row + c, 8);
    const std::uint64_t marked = marks(word ^ pattern);
    if (marked != 0) return c + __builtin_ctzll(marked) / 8;
  }
#else
  (void)value;
  (void)marks;
#endif
  while (c < to && !wanted(row[c])) ++c;
  return c;
}

/// The first index in [from, to) whose byte differs from `value`, or `to`.
inline int find_byte_not_equal(const std::uint8_t* row, int from, int to, std::uint8_t value) {
  // Non-zero bytes of word ^ pattern are the ones that differ.
  return find_first_byte(row, from, to, value, [](std::uint64_t x) { return x; },
                         [value](std::uint8_t b) { return b != value; });
}

/// The first index in [from, to) whose byte equals `value`, or `to`.
inline int find_byte_equal(const std::uint8_t* row, int from, int to, std::uint8_t value) {
  // Zero bytes of word ^ pattern are the equal ones.
  return find_first_byte(row, from, to, value, [](std::uint64_t x) { return zero_byte_marks(x); },
                         [value](std::uint8_t b) { return b == value; });
}

/// How many of the `count` bytes at `bytes` equal `value`.
inline std::size_t count_byte_equal(const std::uint8_t* bytes, std::size_t count, std::uint8_t value) {
  std::size_t n = 0, i = 0;
#ifdef AREAMATCH_WORD_SCAN
  const std::uint64_t pattern = 0x0101010101010101ULL * value;
  for (; i + 8 <= count; i += 8) {
    std::uint64_t word;
    std::memcpy(&word, bytes + i, 8);
    // The multiplication sums the marks into the top byte (no popcount instruction needed).
    const std::uint64_t equal = zero_byte_marks(word ^ pattern);
    n += static_cast<std::size_t>(((equal >> 7) * 0x0101010101010101ULL) >> 56);
  }
#endif
  for (; i < count; ++i) n += bytes[i] == value;
  return n;
}

/// The zero 16-bit lanes of `x` with their high bit set, and nothing else.
inline std::uint64_t zero_lane16_marks(std::uint64_t x) {
  constexpr std::uint64_t low15 = 0x7FFF7FFF7FFF7FFFULL;
  return ~(((x & low15) + low15) | x | low15);
}

/// The first index in [from, to) of a row of values (a mask's bytes, the area stage's working
/// labels) that equals `value` (`equal`) or differs from it, or `to`. Bytes by the byte scans,
/// 16-bit values four per step in the same way.
template <class T>
int find_value(const T* row, int from, int to, T value, bool equal) {
  if constexpr (std::is_same_v<T, std::uint8_t>) {
    return equal ? find_byte_equal(row, from, to, value) : find_byte_not_equal(row, from, to, value);
  }
  int c = from;
#ifdef AREAMATCH_WORD_SCAN
  if constexpr (sizeof(T) == 2) {
    const std::uint64_t pattern = 0x0001000100010001ULL * static_cast<std::uint16_t>(value);
    for (; c + 4 <= to; c += 4) {
      std::uint64_t word;
      std::memcpy(&word, row + c, 8);
      const std::uint64_t differ = word ^ pattern;
      const std::uint64_t marked = equal ? zero_lane16_marks(differ) : differ;
      if (marked != 0) return c + __builtin_ctzll(marked) / 16;
    }
  }
#endif
  while (c < to && (row[c] == value) != equal) ++c;
  return c;
}

}  // namespace areamatch::detail
