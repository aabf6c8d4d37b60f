// A Features policy that is not a FeatureSet: one readable message, nothing else.
#include <areamatch/matcher.hpp>
struct NotAFeatureSet {};
int main() { areamatch::Matcher<areamatch::VoronoiSegmenter, NotAFeatureSet> m; (void)m; }
