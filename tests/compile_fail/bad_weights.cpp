// Two weights for the paper's three features: the Weights message.
#include <areamatch/matcher.hpp>
struct TwoWeights { std::array<double, 2> values{0.5, 0.5}; };
int main() { areamatch::Matcher<areamatch::VoronoiSegmenter, areamatch::PaperFeatures, TwoWeights> m; (void)m; }
