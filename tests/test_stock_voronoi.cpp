// The segmenter built with AREAMATCH_FAST_VORONOI_CIRCLES=0, as on a Boost version whose
// internal Voronoi predicates our faster circle events were not written against: only Boost's
// stock builder is compiled, and segmentation still finds every room. (test_segmentation checks
// that both builders give the same Area Graph where both are compiled.)
#include <areamatch/segment/voronoi_segmenter.hpp>
#include <areamatch/segmentation_score.hpp>
#include <areamatch/synthetic.hpp>

#include <doctest/doctest.h>

#include <cstdint>

static_assert(AREAMATCH_FAST_VORONOI_CIRCLES == 0, "this test is built with the stock Voronoi builder only");

using namespace areamatch;

TEST_CASE("the stock Voronoi builder segments generated buildings into their rooms") {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const auto building = generate_building({}, seed);
    VoronoiSegmenter segmenter;
    const AreaGraph graph = segmenter.segment(building.layout);
    INFO("seed " << seed);
    REQUIRE_FALSE(graph.areas.empty());
    CHECK(graph.passages.size() + 1 >= graph.areas.size());  // a connected building
    const SegmentationScore score = score_segmentation(graph.labels, building.labels, 1);
    CHECK(score.recall > 0.95);
    CHECK(score.precision > 0.9);
  }
}
