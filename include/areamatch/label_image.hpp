#pragma once
/// \file label_image.hpp
/// A label per cell of a map, held as runs of equal labels.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace areamatch {

/// Per cell of a map (image order): an `int` label (for an Area Graph, the id of the area holding
/// the cell, −1 for none). Held as runs of equal labels within chunks of `chunk_cells` cells:
/// a read finds its chunk by index and its run among the chunk's few, so reads stay O(1), and a
/// segmented map takes about a tenth of a byte a cell (a plain array took 2–4, and the labels of
/// two maps were most of a large floor's memory).
///
/// Building is linear: `append`, `assign` and the constructors. `fill` and `set` inside the image
/// re-encode the chunks they touch and shift the runs after them, so each costs time in
/// proportion to the image's runs: for many scattered writes, fill a `std::vector<int>` and assign
/// it. Reading in order (`begin`/`end`, `for_each_run`) is faster than indexing every cell.
class LabelImage {
 public:
  static constexpr std::size_t chunk_cells = 64;

  LabelImage() = default;
  /// `count` cells of `value`.
  LabelImage(std::size_t count, int value) { assign(count, value); }
  LabelImage(std::initializer_list<int> values) { assign(values.begin(), values.end()); }
  explicit LabelImage(const std::vector<int>& values) { assign(values.begin(), values.end()); }

  /// `count` cells of `value`.
  void assign(std::size_t count, int value) {
    clear();
    append(count, value);
  }
  template <class Iterator, class = std::enable_if_t<!std::is_integral_v<Iterator>>>
  void assign(Iterator first, Iterator last) {
    clear();
    for (; first != last; ++first) append(1, static_cast<int>(*first));
  }
  void clear() {
    size_ = 0;
    chunk_first_.assign(1, 0);
    run_offset_.clear();
    run_label_.clear();
  }

  /// Adds `count` cells of `value` at the end.
  void append(std::size_t count, int value) {
    if (chunk_first_.empty()) chunk_first_.assign(1, 0);
    while (count > 0) {
      const std::size_t offset = size_ % chunk_cells;
      const std::size_t take = std::min(count, chunk_cells - offset);
      if (offset == 0) {  // a new chunk: its first run starts it
        push_run(0, value);
        chunk_first_.push_back(static_cast<std::uint32_t>(run_label_.size()));
      } else if (run_label_.back() != value) {
        push_run(offset, value);
        chunk_first_.back() = static_cast<std::uint32_t>(run_label_.size());
      }
      size_ += take;
      count -= take;
    }
  }

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  int operator[](std::size_t i) const {
    const std::size_t chunk = i / chunk_cells;
    const auto offset = static_cast<std::uint8_t>(i % chunk_cells);
    std::uint32_t run = chunk_first_[chunk];
    const std::uint32_t end = chunk_first_[chunk + 1];
    while (run + 1 < end && run_offset_[run + 1] <= offset) ++run;
    return run_label_[run];
  }

  /// Cells [first, last) set to `value` (first ≤ last ≤ size()).
  void fill(std::size_t first, std::size_t last, int value) {
    if (first > last || last > size_) throw std::out_of_range("LabelImage::fill: cells outside the image");
    if (first == last) return;
    const std::size_t c0 = first / chunk_cells, c1 = (last - 1) / chunk_cells;
    // The touched chunks re-encoded: one run for a chunk covered whole, the others decoded,
    // written and encoded again.
    std::vector<std::uint8_t> offsets;
    std::vector<std::int32_t> labels;
    std::vector<std::uint32_t> runs_in_chunk;
    std::array<int, chunk_cells> cells{};
    for (std::size_t c = c0; c <= c1; ++c) {
      const std::size_t base = c * chunk_cells, count = std::min(chunk_cells, size_ - base);
      const std::size_t before = labels.size();
      if (first <= base && base + count <= last) {
        offsets.push_back(0);
        labels.push_back(value);
      } else {
        decode_chunk(c, cells.data());
        std::fill(cells.begin() + static_cast<std::ptrdiff_t>(std::max(first, base) - base),
                  cells.begin() + static_cast<std::ptrdiff_t>(std::min(last, base + count) - base), value);
        for (std::size_t k = 0; k < count; ++k) {
          if (k == 0 || cells[k] != labels.back()) {
            offsets.push_back(static_cast<std::uint8_t>(k));
            labels.push_back(cells[k]);
          }
        }
      }
      runs_in_chunk.push_back(static_cast<std::uint32_t>(labels.size() - before));
    }
    // Spliced in place of the chunks' old runs; the chunks after shift by the difference.
    const std::uint32_t old_first = chunk_first_[c0], old_last = chunk_first_[c1 + 1];
    const auto at = static_cast<std::ptrdiff_t>(old_first);
    const auto old_end = static_cast<std::ptrdiff_t>(old_last);
    if (run_label_.size() - (old_last - old_first) + labels.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw std::length_error("LabelImage: more than 2^32 runs");
    }
    run_offset_.erase(run_offset_.begin() + at, run_offset_.begin() + old_end);
    run_label_.erase(run_label_.begin() + at, run_label_.begin() + old_end);
    run_offset_.insert(run_offset_.begin() + at, offsets.begin(), offsets.end());
    run_label_.insert(run_label_.begin() + at, labels.begin(), labels.end());
    std::uint32_t next = old_first;
    for (std::size_t c = c0; c <= c1; ++c) {
      chunk_first_[c] = next;
      next += runs_in_chunk[c - c0];
    }
    const std::int64_t shift = static_cast<std::int64_t>(next) - static_cast<std::int64_t>(old_last);
    for (std::size_t c = c1 + 1; c < chunk_first_.size(); ++c) {
      chunk_first_[c] = static_cast<std::uint32_t>(static_cast<std::int64_t>(chunk_first_[c]) + shift);
    }
  }
  void set(std::size_t i, int value) { fill(i, i + 1, value); }

  /// Calls `visit(first, last, label)` for each stretch of equal labels within cells
  /// [first, last), in order (stretches are as long as they can be).
  template <class Visit>
  void for_each_run(std::size_t first, std::size_t last, Visit&& visit) const {
    last = std::min(last, size_);
    if (first >= last) return;
    std::size_t chunk = first / chunk_cells;
    std::uint32_t run = chunk_first_[chunk];
    while (run + 1 < chunk_first_[chunk + 1] && chunk * chunk_cells + run_offset_[run + 1] <= first) ++run;
    std::size_t begin = first;
    int label = run_label_[run];
    for (;;) {
      std::size_t end = run_end(run, chunk);
      if (end >= last) break;
      // The next run, possibly in the next chunk.
      if (++run == chunk_first_[chunk + 1]) ++chunk;
      if (run_label_[run] != label) {
        visit(begin, end, label);
        begin = end;
        label = run_label_[run];
      }
    }
    visit(begin, last, label);
  }
  template <class Visit>
  void for_each_run(Visit&& visit) const {
    for_each_run(0, size_, std::forward<Visit>(visit));
  }

  std::vector<int> to_vector() const { return std::vector<int>(begin(), end()); }
  /// Bytes held (a plain `int` array holds 4 a cell).
  std::size_t memory_bytes() const {
    return chunk_first_.capacity() * sizeof(std::uint32_t) + run_offset_.capacity() + run_label_.capacity() * sizeof(std::int32_t);
  }
  /// Lets go of the slack left by building.
  void shrink_to_fit() {
    chunk_first_.shrink_to_fit();
    run_offset_.shrink_to_fit();
    run_label_.shrink_to_fit();
  }

  /// Reads the labels in order as `int`s, a run at a time (for range-for and copies).
  class const_iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = int;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = int;
    const_iterator(const LabelImage* image, std::size_t i) : image_(image), i_(i) {
      if (i_ < image_->size_) run_end_ = image_->run_end(0, 0);
    }
    int operator*() const { return image_->run_label_[run_]; }
    const_iterator& operator++() {
      if (++i_ == run_end_ && i_ < image_->size_) {
        if (++run_ == image_->chunk_first_[chunk_ + 1]) ++chunk_;
        run_end_ = image_->run_end(run_, chunk_);
      }
      return *this;
    }
    const_iterator operator++(int) {
      const_iterator before = *this;
      ++*this;
      return before;
    }
    friend bool operator==(const const_iterator& a, const const_iterator& b) { return a.i_ == b.i_; }
    friend bool operator!=(const const_iterator& a, const const_iterator& b) { return a.i_ != b.i_; }

   private:
    const LabelImage* image_;
    std::size_t i_;
    std::uint32_t run_ = 0;
    std::size_t chunk_ = 0;
    std::size_t run_end_ = 0;  ///< the first cell after the current run
  };
  const_iterator begin() const { return {this, 0}; }
  const_iterator end() const { return {this, size_}; }

  /// Equal when every cell is (the encoding is canonical: runs within a chunk differ in label).
  friend bool operator==(const LabelImage& a, const LabelImage& b) {
    return a.size_ == b.size_ && a.run_label_ == b.run_label_ && a.run_offset_ == b.run_offset_ && a.chunk_first_ == b.chunk_first_;
  }
  friend bool operator!=(const LabelImage& a, const LabelImage& b) { return !(a == b); }

 private:
  void push_run(std::size_t offset, int value) {
    if (run_label_.size() >= std::numeric_limits<std::uint32_t>::max()) throw std::length_error("LabelImage: more than 2^32 runs");
    run_offset_.push_back(static_cast<std::uint8_t>(offset));
    run_label_.push_back(value);
  }
  /// The first cell after run `run` of chunk `chunk`.
  std::size_t run_end(std::uint32_t run, std::size_t chunk) const {
    const std::size_t base = chunk * chunk_cells;
    if (run + 1 < chunk_first_[chunk + 1]) return base + run_offset_[run + 1];
    return std::min(base + chunk_cells, size_);
  }
  void decode_chunk(std::size_t chunk, int* cells) const {
    const std::size_t base = chunk * chunk_cells;
    for (std::uint32_t run = chunk_first_[chunk]; run < chunk_first_[chunk + 1]; ++run) {
      std::fill(cells + run_offset_[run], cells + (run_end(run, chunk) - base), run_label_[run]);
    }
  }

  std::size_t size_ = 0;
  std::vector<std::uint32_t> chunk_first_{0};  ///< each chunk's first run, and the run count last
  std::vector<std::uint8_t> run_offset_;       ///< where each run starts in its chunk
  std::vector<std::int32_t> run_label_;
};

}  // namespace areamatch
