#pragma once
/// \file match/inputs.hpp
/// What the matcher checks of the maps it is given before matching: each Area Graph made from its
/// grid, no scale to estimate where the caller segmented the source, and the area limit.

#include "../area_graph.hpp"
#include "../error.hpp"
#include "../grid.hpp"
#include "params.hpp"

#include <string>
#include <utility>

namespace areamatch {
namespace detail {

/// Whether `graph` was made from `grid` (the same cells).
inline bool graph_fits(const OccupancyGrid& grid, const AreaGraph& graph) {
  return graph.grid.width == grid.width() && graph.grid.height == grid.height() && graph.labels.size() == grid.cells().size();
}

inline void check_graph(const OccupancyGrid& grid, const AreaGraph& graph, const char* which) {
  if (!graph_fits(grid, graph)) {
    throw parameter_error(std::string("Matcher::match: the ") + which + " Area Graph was not made from the " + which +
                          " grid (sizes differ)");
  }
}

/// What matching two maps segmented by the caller needs: no scale to estimate (that segments
/// the source itself), and each graph made from its grid.
inline void check_segmented(const MatcherParams& params, const OccupancyGrid& source, const AreaGraph& source_graph,
                            const OccupancyGrid& dest, const AreaGraph& dest_graph) {
  if (params.estimate_scale) {
    throw parameter_error("Matcher::match: estimate_scale re-segments the source at each candidate scale; pass the "
                          "source grid (match(source, dest) or match_estimating_scale), not its graph");
  }
  check_graph(source, source_graph, "source");
  check_graph(dest, dest_graph, "destination");
}

/// Refuses maps with more areas than `MatcherParams::max_areas`.
inline void check_area_limit(const MatcherParams& params, const AreaGraph& source, const AreaGraph& dest) {
  for (const auto& [graph, which] : {std::pair{&source, "source"}, std::pair{&dest, "destination"}}) {
    if (graph->areas.size() > params.max_areas) {
      throw limit_error(std::string("the ") + which + " map has " + std::to_string(graph->areas.size()) +
                        " areas, more than MatcherParams::max_areas (" + std::to_string(params.max_areas) +
                        "); raise it if the map really has that many rooms, or clean the map (a map shattered into "
                        "pieces by noise read as walls) or match parts of it");
    }
  }
}

}  // namespace detail
}  // namespace areamatch
