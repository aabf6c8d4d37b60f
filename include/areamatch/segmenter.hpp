#pragma once
/// \file segmenter.hpp
/// The segmenter concept: what a policy that turns an occupancy grid into an Area Graph provides.
///
/// A segmenter is a copyable type with a const member function
/// `AreaGraph segment(const OccupancyGrid&) const`. The smallest conforming type:
/// \code
/// struct WholeMapSegmenter {                       // one area: all free space
///   areamatch::AreaGraph segment(const areamatch::OccupancyGrid& grid) const;
/// };
/// \endcode
/// `VoronoiSegmenter` (segment/voronoi_segmenter.hpp) is the default.

#include "area_graph.hpp"
#include "grid.hpp"

#include <type_traits>
#include <utility>

namespace areamatch {

template <class S, class = void>
struct is_segmenter : std::false_type {};

template <class S>
struct is_segmenter<S, std::void_t<decltype(std::declval<const S&>().segment(std::declval<const OccupancyGrid&>()))>>
    : std::is_convertible<decltype(std::declval<const S&>().segment(std::declval<const OccupancyGrid&>())), AreaGraph> {};

template <class S>
inline constexpr bool is_segmenter_v = is_segmenter<S>::value;

/// Fails to compile with a readable message when S is not a segmenter.
template <class S>
constexpr void check_segmenter() {
  static_assert(is_segmenter_v<S>,
                "areamatch: a Segmenter policy needs a const member function "
                "`areamatch::AreaGraph segment(const areamatch::OccupancyGrid&) const` (see segmenter.hpp)");
}

}  // namespace areamatch
