// A segmenter without `segment(const OccupancyGrid&) const`: the Segmenter message.
#include <areamatch/matcher.hpp>
struct NoSegment {};
int main() { areamatch::Matcher<NoSegment> m; (void)m; }
