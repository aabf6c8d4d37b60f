#pragma once
/// \file area_graph.hpp
/// The Area Graph: areas (rooms, corridors) as nodes, passages (doors, junctions) as edges.
/// Everything in metres in the source map's world frame.

#include "geometry.hpp"
#include "grid.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <string>
#include <type_traits>
#include <vector>

namespace areamatch {

/// What an area looks like (a hint from its shape, not ground truth).
enum class AreaKind : std::uint8_t {
  room,      ///< compact
  corridor,  ///< long and narrow: its hull diameter is over `corridor_elongation` × its width
  other      ///< for custom segmenters; VoronoiSegmenter assigns only room and corridor
};

inline const char* to_string(AreaKind kind) {
  return kind == AreaKind::room ? "room" : kind == AreaKind::corridor ? "corridor" : "other";
}

/// What joins two areas.
enum class PassageKind : std::uint8_t {
  door,     ///< a narrowing of free space between two areas
  junction  ///< where corridor pieces meet
};

inline const char* to_string(PassageKind kind) { return kind == PassageKind::door ? "door" : "junction"; }

/// An opening between two areas.
struct Passage {
  int id = -1;
  PassageKind kind = PassageKind::door;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< centre of the opening
  double width_m = 0.0;                                ///< clear width of the opening
  int area_a = -1;                                     ///< the two areas it joins (a < b)
  int area_b = -1;
  Segment2 line;                                       ///< across the opening, wall to wall
};

/// A room or corridor.
struct Area {
  int id = -1;
  AreaKind kind = AreaKind::room;
  Polygon2 polygon;                                    ///< valid, with holes (furniture, pillars)
  double size_m2 = 0.0;                                ///< area of the free cells it holds
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  Polygon2 convex_hull;
  double max_clearance_m = 0.0;                        ///< radius of the largest free disc in it
  std::vector<int> passages;                           ///< ids of its passages, ascending
};

/// The source grid's frame, so results can go back to pixels.
struct GridInfo {
  int width = 0;
  int height = 0;
  double resolution = 0.05;
  Pose2 origin{};

  /// The frame of `grid`.
  static GridInfo of(const OccupancyGrid& grid) { return {grid.width(), grid.height(), grid.resolution(), grid.origin()}; }

  /// Continuous pixel coordinates (col, row) → world metres, as `OccupancyGrid::world_from_pixel`.
  Eigen::Affine2d world_from_pixel() const { return detail::world_from_pixel(height, resolution, origin); }

  friend bool operator==(const GridInfo& a, const GridInfo& b) {
    return a.width == b.width && a.height == b.height && a.resolution == b.resolution && a.origin == b.origin;
  }
};

/// Per cell of a map (image order): the id of the area holding it, −1 for none. Held in 16 bits
/// while every value fits (up to 32767 areas), in 32 bits otherwise; reads give `int` either
/// way. The labels of two maps were most of a large floor's match memory at 4 bytes a cell.
class LabelImage {
 public:
  LabelImage() = default;
  /// `count` cells of `value`.
  LabelImage(std::size_t count, int value) { assign(count, value); }
  LabelImage(std::initializer_list<int> values) { assign(values.begin(), values.end()); }
  explicit LabelImage(const std::vector<int>& values) { assign(values.begin(), values.end()); }

  /// `count` cells of `value`, held wide enough for ids up to `largest` (more only widens later).
  void assign(std::size_t count, int value, int largest = 0) {
    std::vector<std::int16_t>().swap(narrow_);
    std::vector<std::int32_t>().swap(wide_);
    is_wide_ = !fits(value) || !fits(largest);
    if (is_wide_) wide_.assign(count, value);
    else narrow_.assign(count, static_cast<std::int16_t>(value));
  }
  template <class Iterator, class = std::enable_if_t<!std::is_integral_v<Iterator>>>
  void assign(Iterator first, Iterator last) {
    const std::vector<int> values(first, last);
    const auto [low, high] = std::minmax_element(values.begin(), values.end());
    assign(0, low == values.end() ? 0 : *low, high == values.end() ? 0 : *high);
    if (is_wide_) wide_.assign(values.begin(), values.end());
    else narrow_.assign(values.begin(), values.end());
  }

  std::size_t size() const { return is_wide_ ? wide_.size() : narrow_.size(); }
  bool empty() const { return size() == 0; }
  int operator[](std::size_t i) const { return is_wide_ ? wide_[i] : narrow_[i]; }
  /// Cells [first, last) set to `value` (the image widens if `value` needs it).
  void fill(std::size_t first, std::size_t last, int value) {
    if (!is_wide_ && !fits(value)) widen();
    if (is_wide_) std::fill(wide_.begin() + static_cast<std::ptrdiff_t>(first), wide_.begin() + static_cast<std::ptrdiff_t>(last), value);
    else std::fill(narrow_.begin() + static_cast<std::ptrdiff_t>(first), narrow_.begin() + static_cast<std::ptrdiff_t>(last),
                   static_cast<std::int16_t>(value));
  }
  void set(std::size_t i, int value) { fill(i, i + 1, value); }
  std::vector<int> to_vector() const {
    return is_wide_ ? std::vector<int>(wide_.begin(), wide_.end()) : std::vector<int>(narrow_.begin(), narrow_.end());
  }
  /// Bytes held per cell: 2, or 4 once wide.
  std::size_t bytes_per_cell() const { return is_wide_ ? 4 : 2; }

  /// Reads the labels in order as `int`s (for range-for and copies).
  class const_iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = int;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = int;
    const_iterator(const LabelImage* image, std::size_t i) : image_(image), i_(i) {}
    int operator*() const { return (*image_)[i_]; }
    const_iterator& operator++() {
      ++i_;
      return *this;
    }
    const_iterator operator++(int) {
      const_iterator before = *this;
      ++i_;
      return before;
    }
    friend bool operator==(const const_iterator& a, const const_iterator& b) { return a.i_ == b.i_; }
    friend bool operator!=(const const_iterator& a, const const_iterator& b) { return a.i_ != b.i_; }

   private:
    const LabelImage* image_;
    std::size_t i_;
  };
  const_iterator begin() const { return {this, 0}; }
  const_iterator end() const { return {this, size()}; }

  friend bool operator==(const LabelImage& a, const LabelImage& b) {
    if (a.size() != b.size()) return false;
    if (a.is_wide_ == b.is_wide_) return a.is_wide_ ? a.wide_ == b.wide_ : a.narrow_ == b.narrow_;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (a[i] != b[i]) return false;
    }
    return true;
  }
  friend bool operator!=(const LabelImage& a, const LabelImage& b) { return !(a == b); }

 private:
  static bool fits(int v) { return v >= INT16_MIN && v <= INT16_MAX; }
  void widen() {
    wide_.assign(narrow_.begin(), narrow_.end());
    std::vector<std::int16_t>().swap(narrow_);
    is_wide_ = true;
  }
  bool is_wide_ = false;
  std::vector<std::int16_t> narrow_;
  std::vector<std::int32_t> wide_;
};

/// Areas and passages of one map, with a label per cell.
struct AreaGraph {
  GridInfo grid;
  std::vector<Area> areas;
  std::vector<Passage> passages;
  /// Per cell of the source grid (image order): the id of the area holding it, −1 for none.
  LabelImage labels;
  /// Share of the map's free cells that belong to some area (laser streaks outside the
  /// building and crumbs too thin to pass are left out on purpose).
  double covered_fraction = 0.0;
  /// Why there are no areas (empty when there are some): no free cells, free space too narrow
  /// to pass, or every piece smaller than the minimum area.
  std::string reason;

  /// Neighbouring areas (through any passage) of each area, ascending, without repeats.
  std::vector<std::vector<int>> adjacency() const {
    std::vector<std::vector<int>> adj(areas.size());
    for (const auto& p : passages) {
      adj[p.area_a].push_back(p.area_b);
      adj[p.area_b].push_back(p.area_a);
    }
    for (auto& list : adj) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    return adj;
  }
};

}  // namespace areamatch
